#include "slamkit/factors/calibration_factors.h"

#include <cmath>

#include "slamkit/core/pose_graph_error.h"

namespace slamkit {

Eigen::Vector3d offset_between_error(const SE2& Z, const SE2& Xi, const SE2& Xj, const SE2& Sa, const SE2& Sb,
                                     Eigen::Matrix3d* J_i, Eigen::Matrix3d* J_j, Eigen::Matrix3d* J_a,
                                     Eigen::Matrix3d* J_b) {
  Eigen::Matrix3d J_pi, J_pj;
  const bool jac = J_i || J_j || J_a || J_b;
  const Eigen::Vector3d e = pose2_edge_error(Z, Xi * Sa, Xj * Sb, jac ? &J_pi : nullptr, jac ? &J_pj : nullptr);
  if (J_i) *J_i = J_pi * Sa.inverse().adjoint();
  if (J_j) *J_j = J_pj * Sb.inverse().adjoint();
  if (J_a) *J_a = J_pi;
  if (J_b) *J_b = J_pj;
  return e;
}

Eigen::Matrix<double, 6, 1> offset_between_error(const SE3& Z, const SE3& Xi, const SE3& Xj, const SE3& Sa,
                                                 const SE3& Sb, Eigen::Matrix<double, 6, 6>* J_i,
                                                 Eigen::Matrix<double, 6, 6>* J_j, Eigen::Matrix<double, 6, 6>* J_a,
                                                 Eigen::Matrix<double, 6, 6>* J_b) {
  Matrix6d J_pi, J_pj;
  const bool jac = J_i || J_j || J_a || J_b;
  const Vector6d e = pose3_edge_error(Z, Xi * Sa, Xj * Sb, jac ? &J_pi : nullptr, jac ? &J_pj : nullptr);
  if (J_i) *J_i = J_pi * Sa.inverse().adjoint();
  if (J_j) *J_j = J_pj * Sb.inverse().adjoint();
  if (J_a) *J_a = J_pi;
  if (J_b) *J_b = J_pj;
  return e;
}

template <class G>
typename SensorOffsetFactor<G>::Residual SensorOffsetFactor<G>::error(const G& Xi, const G& Xj, const G& S, GJ* J_i,
                                                                      GJ* J_j, GJ* J_s) const {
  GJ J_a, J_b;
  const Residual e = offset_between_error(measured_, Xi, Xj, S, S, J_i, J_j, J_s ? &J_a : nullptr, J_s ? &J_b : nullptr);
  if (J_s) *J_s = J_a + J_b;  // S appears on both sides
  return e;
}

template <class G>
typename SensorOffsetPairFactor<G>::Residual SensorOffsetPairFactor<G>::error(const G& Xi, const G& Xj, const G& Sa,
                                                                              const G& Sb, GJ* J_i, GJ* J_j, GJ* J_a,
                                                                              GJ* J_b) const {
  return offset_between_error(measured_, Xi, Xj, Sa, Sb, J_i, J_j, J_a, J_b);
}

template class SensorOffsetFactor<SE2>;
template class SensorOffsetFactor<SE3>;
template class SensorOffsetPairFactor<SE2>;
template class SensorOffsetPairFactor<SE3>;

Eigen::Vector3d pose2_error_wrt_measurement(const Eigen::Vector3d& u, const SE2& Xi, const SE2& Xj,
                                            Eigen::Matrix3d* J_i, Eigen::Matrix3d* J_j, Eigen::Matrix3d* J_u) {
  const SE2 U(u[0], u[1], u[2]);
  const Eigen::Vector3d e = pose2_edge_error(U, Xi, Xj, J_i, J_j);
  if (J_u) {
    // e_t = R_Uᵀ (t_A − t_U), e_θ = θ_A − θ_U: ∂e_t/∂t_U = −R_Uᵀ, ∂e_t/∂θ_U = (e_y, −e_x).
    J_u->setZero();
    J_u->topLeftCorner<2, 2>() = -U.rotation().matrix().transpose();
    (*J_u)(0, 2) = e.y();
    (*J_u)(1, 2) = -e.x();
    (*J_u)(2, 2) = -1.0;
  }
  return e;
}

DifferentialDriveOdometryFactor::Residual DifferentialDriveOdometryFactor::error(
    const SE2& Xi, const SE2& Xj, const Eigen::Vector3d& K, Jacobian<SE2>* J_i, Jacobian<SE2>* J_j,
    Jacobian<Eigen::Vector3d>* J_k) const {
  Eigen::Matrix3d J_motion_K, J_e_u;
  const Eigen::Vector3d u = differential_drive_motion(K, measured_[0], measured_[1], measured_[2], J_k ? &J_motion_K : nullptr);
  const Eigen::Vector3d e = pose2_error_wrt_measurement(u, Xi, Xj, J_i, J_j, J_k ? &J_e_u : nullptr);
  if (J_k) *J_k = J_e_u * J_motion_K;
  return e;
}

LinearOdometryFactor::Residual LinearOdometryFactor::error(const SE2& Xi, const SE2& Xj, const Vector9d& K,
                                                           Jacobian<SE2>* J_i, Jacobian<SE2>* J_j,
                                                           Jacobian<Vector9d>* J_k) const {
  const Eigen::Matrix3d M = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(K.data());
  const Eigen::Vector3d u = M * measured_;
  Eigen::Matrix3d J_e_u;
  const Eigen::Vector3d e = pose2_error_wrt_measurement(u, Xi, Xj, J_i, J_j, J_k ? &J_e_u : nullptr);
  if (J_k) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) J_k->col(3 * r + c) = J_e_u.col(r) * measured_[c];
  }
  return e;
}

Vector9d identity_linear_odometry() {
  Vector9d k;
  k << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  return k;
}

}  // namespace slamkit
