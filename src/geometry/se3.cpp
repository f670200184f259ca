#include "slamkit/geometry/se3.h"

namespace slamkit {

namespace {
// Q(ρ, φ) of the SE(3) left Jacobian (Barfoot, eq. 7.86).
Eigen::Matrix3d q_block(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  using namespace lie_detail;
  const double theta = phi.norm();
  const Eigen::Matrix3d P = skew(phi), Rh = skew(rho);
  const Eigen::Matrix3d PR = P * Rh, RP = Rh * P, PRP = PR * P;
  return 0.5 * Rh + t_minus_sin_over_t3(theta) * (PR + RP + PRP) +
         se3_q_coefficient2(theta) * (P * PR + RP * P - 3.0 * PRP) +
         se3_q_coefficient3(theta) * (PRP * P + P * PRP);
}
}  // namespace

SE3 SE3::from_matrix(const Eigen::Matrix<double, 3, 4>& T) {
  return SE3(SO3::from_matrix(T.leftCols<3>()), T.col(3));
}

Eigen::Matrix4d SE3::matrix() const {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R_.matrix();
  T.topRightCorner<3, 1>() = t_;
  return T;
}

SE3 SE3::exp(const Tangent& tau, Jacobian* J_out_tau) {
  const Eigen::Vector3d rho = tau.head<3>(), phi = tau.tail<3>();
  const SE3 T(SO3::exp(phi), SO3::left_jacobian(phi) * rho);
  if (J_out_tau) *J_out_tau = right_jacobian(tau);
  return T;
}

SE3::Tangent SE3::log(Jacobian* J_out_this) const {
  const Eigen::Vector3d phi = R_.log();
  Tangent tau;
  tau << SO3::left_jacobian_inverse(phi) * t_, phi;
  if (J_out_this) *J_out_this = right_jacobian_inverse(tau);
  return tau;
}

SE3 SE3::compose(const SE3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  if (J_out_this) *J_out_this = other.inverse().adjoint();
  if (J_out_other) J_out_other->setIdentity();
  return SE3(R_ * other.R_, t_ + R_.act(other.t_));
}

SE3 SE3::inverse(Jacobian* J_out_this) const {
  if (J_out_this) *J_out_this = -adjoint();
  const SO3 Rinv = R_.inverse();
  return SE3(Rinv, -Rinv.act(t_));
}

SE3 SE3::between(const SE3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  const SE3 d = inverse() * other;
  if (J_out_this) *J_out_this = -d.inverse().adjoint();
  if (J_out_other) J_out_other->setIdentity();
  return d;
}

Eigen::Vector3d SE3::act(const Eigen::Vector3d& p, Eigen::Matrix<double, 3, 6>* J_out_this,
                         Eigen::Matrix3d* J_out_p) const {
  const Eigen::Matrix3d R = R_.matrix();
  if (J_out_this) {
    J_out_this->leftCols<3>() = R;
    J_out_this->rightCols<3>() = -R * skew(p);
  }
  if (J_out_p) *J_out_p = R;
  return R * p + t_;
}

SE3::Jacobian SE3::adjoint() const {
  const Eigen::Matrix3d R = R_.matrix();
  Jacobian Ad;
  Ad << R, skew(t_) * R, Eigen::Matrix3d::Zero(), R;
  return Ad;
}

SE3 SE3::plus(const Tangent& delta, Jacobian* J_out_this, Jacobian* J_out_delta) const {
  const SE3 step = exp(delta, J_out_delta);
  if (J_out_this) *J_out_this = step.inverse().adjoint();
  return *this * step;
}

SE3::Tangent SE3::minus(const SE3& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  const Tangent tau = other.between(*this).log();
  if (J_out_this) *J_out_this = right_jacobian_inverse(tau);
  if (J_out_other) *J_out_other = -left_jacobian_inverse(tau);
  return tau;
}

SE3::Jacobian SE3::right_jacobian(const Tangent& tau) {
  // Jr(ρ, φ) = Jl(−ρ, −φ).
  const Eigen::Vector3d rho = -tau.head<3>(), phi = -tau.tail<3>();
  const Eigen::Matrix3d Jl = SO3::left_jacobian(phi);
  Jacobian J;
  J << Jl, q_block(rho, phi), Eigen::Matrix3d::Zero(), Jl;
  return J;
}

SE3::Jacobian SE3::right_jacobian_inverse(const Tangent& tau) {
  // [[A, B], [0, A]]⁻¹ = [[A⁻¹, −A⁻¹ B A⁻¹], [0, A⁻¹]] with A = Jr(φ), B = Q(−ρ, −φ).
  const Eigen::Vector3d phi = tau.tail<3>();
  const Eigen::Matrix3d Ainv = SO3::right_jacobian_inverse(phi);
  const Eigen::Matrix3d B = q_block(-tau.head<3>(), -phi);
  Jacobian J;
  J << Ainv, -Ainv * B * Ainv, Eigen::Matrix3d::Zero(), Ainv;
  return J;
}

}  // namespace slamkit
