#include "slamkit/factors/inverse_depth_factor.h"

#include "slamkit/geometry/lie_math.h"

namespace slamkit {

Eigen::Vector3d InverseDepthFactor::world_point(const ImuState& xa, double rho) const {
  return xa.R.act(T_imu_cam_.act(bearing_ / rho)) + xa.p;
}

InverseDepthFactor::Residual InverseDepthFactor::error(const ImuState& xa, const ImuState& xk, const InverseDepth& rho,
                                                       Jacobian<ImuState>* J_a, Jacobian<ImuState>* J_k,
                                                       Jacobian<InverseDepth>* J_rho) const {
  const Eigen::Matrix3d R_bc = T_imu_cam_.rotation().matrix();
  const Eigen::Matrix3d Ra = xa.R.matrix(), RkT = xk.R.matrix().transpose();
  const double r = rho(0);
  const Eigen::Vector3d P_ba = T_imu_cam_.act(bearing_ / r);  // R_bc P_a + t_bc
  const Eigen::Vector3d P_w = Ra * P_ba + xa.p;
  const Eigen::Vector3d P_bk = RkT * (P_w - xk.p);
  const Eigen::Vector3d P_k = R_bc.transpose() * (P_bk - T_imu_cam_.translation());
  Eigen::Vector2d uv;
  Eigen::Matrix<double, 2, 3> J_pi;
  if (!camera_->project(P_k, &uv, &J_pi)) {
    if (J_a) J_a->setZero();
    if (J_k) J_k->setZero();
    if (J_rho) J_rho->setZero();
    return Residual(kOutOfView, kOutOfView);
  }
  if (J_a || J_k || J_rho) {
    const Eigen::Matrix<double, 2, 3> J_Pbk = J_pi * R_bc.transpose();  // ∂r/∂P_bk
    const Eigen::Matrix<double, 2, 3> J_Pw = J_Pbk * RkT;               // ∂r/∂P_w
    if (J_a) {
      J_a->setZero();
      J_a->block<2, 3>(0, 0) = -J_Pw * Ra * skew(P_ba);
      J_a->block<2, 3>(0, 6) = J_Pw;
    }
    if (J_k) {
      J_k->setZero();
      J_k->block<2, 3>(0, 0) = J_Pbk * skew(P_bk);
      J_k->block<2, 3>(0, 6) = -J_Pbk * RkT;
    }
    if (J_rho) *J_rho = J_Pw * (Ra * R_bc * (-bearing_ / (r * r)));
  }
  return uv - measured_;
}

}  // namespace slamkit
