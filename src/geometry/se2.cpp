#include "slamkit/geometry/se2.h"

namespace slamkit {

using lie_detail::one_minus_cos_over_t2;
using lie_detail::sinc;
using lie_detail::t_minus_sin_over_t3;

namespace {
// V(θ) = [[a, −b], [b, a]] with a = sin θ/θ, b = (1 − cos θ)/θ.
void v_coefficients(double theta, double* a, double* b) {
  *a = sinc(theta);
  *b = theta * one_minus_cos_over_t2(theta);
}
}  // namespace

Eigen::Matrix3d SE2::matrix() const {
  Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
  T.topLeftCorner<2, 2>() = R_.matrix();
  T.topRightCorner<2, 1>() = t_;
  return T;
}

SE2 SE2::exp(const Tangent& tau, Jacobian* J_out_tau) {
  double a, b;
  v_coefficients(tau.z(), &a, &b);
  const Eigen::Vector2d t(a * tau.x() - b * tau.y(), b * tau.x() + a * tau.y());
  if (J_out_tau) *J_out_tau = right_jacobian(tau);
  return SE2(SO2(tau.z()), t);
}

SE2::Tangent SE2::log(Jacobian* J_out_this) const {
  const double theta = R_.angle();
  double a, b;
  v_coefficients(theta, &a, &b);
  const double inv_det = 1.0 / (a * a + b * b);  // ≥ π²/4 for θ ∈ (−π, π]
  Tangent tau(inv_det * (a * t_.x() + b * t_.y()), inv_det * (-b * t_.x() + a * t_.y()), theta);
  if (J_out_this) *J_out_this = right_jacobian_inverse(tau);
  return tau;
}

SE2 SE2::compose(const SE2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) *J_out_this = other.inverse().adjoint();
  if (J_out_other) J_out_other->setIdentity();
  return SE2(R_ * other.R_, t_ + R_.matrix() * other.t_);
}

SE2 SE2::inverse(Jacobian* J_out_this) const {
  if (J_out_this) *J_out_this = -adjoint();
  const SO2 Rinv = R_.inverse();
  return SE2(Rinv, -(Rinv.matrix() * t_));
}

SE2 SE2::between(const SE2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  const SE2 d = inverse() * other;
  if (J_out_this) *J_out_this = -d.inverse().adjoint();
  if (J_out_other) J_out_other->setIdentity();
  return d;
}

Eigen::Vector2d SE2::act(const Eigen::Vector2d& p, Eigen::Matrix<double, 2, 3>* J_out_this,
                         Eigen::Matrix2d* J_out_p) const {
  const Eigen::Matrix2d R = R_.matrix();
  if (J_out_this) {
    J_out_this->leftCols<2>() = R;
    J_out_this->col(2) = R * Eigen::Vector2d(-p.y(), p.x());
  }
  if (J_out_p) *J_out_p = R;
  return R * p + t_;
}

SE2::Jacobian SE2::adjoint() const {
  Jacobian Ad = Jacobian::Identity();
  Ad.topLeftCorner<2, 2>() = R_.matrix();
  Ad(0, 2) = t_.y();
  Ad(1, 2) = -t_.x();
  return Ad;
}

SE2 SE2::plus(const Tangent& delta, Jacobian* J_out_this, Jacobian* J_out_delta) const {
  const SE2 step = exp(delta, J_out_delta);
  if (J_out_this) *J_out_this = step.inverse().adjoint();
  return *this * step;
}

SE2::Tangent SE2::minus(const SE2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  const Tangent tau = other.between(*this).log();
  if (J_out_this) *J_out_this = right_jacobian_inverse(tau);
  if (J_out_other) *J_out_other = -left_jacobian_inverse(tau);
  return tau;
}

SE2::Jacobian SE2::right_jacobian(const Tangent& tau) {
  const double th = tau.z(), r1 = tau.x(), r2 = tau.y();
  const double a = sinc(th), omc = one_minus_cos_over_t2(th), tms = t_minus_sin_over_t3(th);
  Jacobian J;
  J << a, th * omc, r1 * th * tms - r2 * omc,  //
      -th * omc, a, r1 * omc + r2 * th * tms,  //
      0.0, 0.0, 1.0;
  return J;
}

SE2::Jacobian SE2::right_jacobian_inverse(const Tangent& tau) {
  // Jr = [[M, c], [0, 1]] ⇒ Jr⁻¹ = [[M⁻¹, −M⁻¹ c], [0, 1]], M = [[a, b], [−b, a]].
  const Jacobian Jr = right_jacobian(tau);
  const double a = Jr(0, 0), b = Jr(0, 1);
  Eigen::Matrix2d Minv;
  Minv << a, -b, b, a;
  Minv /= (a * a + b * b);
  Jacobian Ji = Jacobian::Identity();
  Ji.topLeftCorner<2, 2>() = Minv;
  Ji.topRightCorner<2, 1>() = -Minv * Jr.topRightCorner<2, 1>();
  return Ji;
}

}  // namespace slamkit
