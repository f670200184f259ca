#include "slamkit/geometry/so3.h"

#include <cmath>
#include <stdexcept>

namespace slamkit {

using lie_detail::jinv_coefficient;
using lie_detail::one_minus_cos_over_t2;
using lie_detail::sinc;
using lie_detail::t_minus_sin_over_t3;

SO3::SO3(const Eigen::Quaterniond& q) {
  const double n = q.norm();
  if (!(n > 0.0) || !std::isfinite(n)) throw std::invalid_argument("SO3: quaternion is zero or not finite");
  q_ = Eigen::Quaterniond(q.coeffs() / n);
}

SO3 SO3::from_matrix(const Eigen::Matrix3d& R) { return SO3(Eigen::Quaterniond(R)); }

SO3 SO3::from_rpy(double roll, double pitch, double yaw) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  return SO3(q);
}

Eigen::Vector3d SO3::to_rpy() const {
  // R = Rz(y) Ry(p) Rx(r). Pitch and yaw come from R; roll from what is left,
  // Ry(p)ᵀ Rz(y)ᵀ R = Rx(r), so it absorbs yaw's error and the angles reproduce R to rounding
  // even at gimbal lock (|p| → π/2), where roll and yaw alone are ill-determined.
  const Eigen::Matrix3d R = matrix();
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const Eigen::Matrix3d rest = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix()
                                   .transpose() *
                               R;
  const double roll = std::atan2(rest(2, 1), rest(1, 1));
  return Eigen::Vector3d(roll, pitch, yaw);
}

SO3 SO3::exp(const Tangent& phi, Jacobian* J_out_phi) {
  const double theta = phi.norm();
  const double half_sinc = 0.5 * sinc(0.5 * theta);  // sin(θ/2)/θ
  const Eigen::Quaterniond q(std::cos(0.5 * theta), half_sinc * phi.x(), half_sinc * phi.y(),
                             half_sinc * phi.z());
  if (J_out_phi) *J_out_phi = right_jacobian(phi);
  return SO3(q, NoNormalize{});
}

SO3::Tangent SO3::log(Jacobian* J_out_this) const {
  // q and −q are one rotation; w ≥ 0 picks θ ∈ [0, π].
  const double sign = q_.w() < 0.0 ? -1.0 : 1.0;
  const double w = sign * q_.w();
  const Eigen::Vector3d v = sign * q_.vec();
  const double n = v.norm();
  double scale;  // θ / ‖v‖
  if (n < 1e-5) {
    scale = 2.0 / w * (1.0 - n * n / (3.0 * w * w));
  } else {
    scale = 2.0 * std::atan2(n, w) / n;
  }
  const Tangent phi = scale * v;
  if (J_out_this) *J_out_this = right_jacobian_inverse(phi);
  return phi;
}

SO3 SO3::compose(const SO3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) *J_out_this = other.matrix().transpose();
  if (J_out_other) J_out_other->setIdentity();
  return SO3((q_ * other.q_).normalized(), NoNormalize{});
}

SO3 SO3::inverse(Jacobian* J_out_this) const {
  if (J_out_this) *J_out_this = -matrix();
  return SO3(q_.conjugate(), NoNormalize{});
}

SO3 SO3::between(const SO3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  const SO3 d((q_.conjugate() * other.q_).normalized(), NoNormalize{});
  if (J_out_this) *J_out_this = -d.matrix().transpose();
  if (J_out_other) J_out_other->setIdentity();
  return d;
}

Eigen::Vector3d SO3::act(const Eigen::Vector3d& p, Jacobian* J_out_this, Eigen::Matrix3d* J_out_p) const {
  const Eigen::Matrix3d R = matrix();
  if (J_out_this) *J_out_this = -R * skew(p);
  if (J_out_p) *J_out_p = R;
  return R * p;
}

SO3 SO3::plus(const Tangent& delta, Jacobian* J_out_this, Jacobian* J_out_delta) const {
  const SO3 step = exp(delta, J_out_delta);
  if (J_out_this) *J_out_this = step.matrix().transpose();
  return *this * step;
}

SO3::Tangent SO3::minus(const SO3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  const Tangent tau = other.between(*this).log();
  if (J_out_this) *J_out_this = right_jacobian_inverse(tau);
  if (J_out_other) *J_out_other = -left_jacobian_inverse(tau);
  return tau;
}

SO3::Jacobian SO3::right_jacobian(const Tangent& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = skew(phi);
  return Jacobian::Identity() - one_minus_cos_over_t2(theta) * K + t_minus_sin_over_t3(theta) * K * K;
}

SO3::Jacobian SO3::right_jacobian_inverse(const Tangent& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = skew(phi);
  return Jacobian::Identity() + 0.5 * K + jinv_coefficient(theta) * K * K;
}

}  // namespace slamkit
