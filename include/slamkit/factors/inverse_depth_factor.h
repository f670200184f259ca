// InverseDepthFactor: reprojection of a feature stored as an inverse depth in its anchor
// keyframe, through a camera model (geometry/camera_models.h) and the IMU–camera extrinsic.
//
// The feature is the unit bearing b (anchor camera frame, from the anchor observation) at
// inverse distance ρ. With states a (anchor) and k (observing), T_imu_cam = (R_bc, t_bc):
//   P_a = b / ρ,  P_w = R_a (R_bc P_a + t_bc) + p_a,  P_k = R_bcᵀ (R_kᵀ (P_w − p_k) − t_bc)
//   r = π(P_k) − z   (pixels)
// Jacobians (tangent of ImuState [δφ, δv, δp, δb_g, δb_a]; only δφ and δp enter):
//   ∂P_w/∂δφ_a = −R_a [R_bc P_a + t_bc]×,  ∂P_w/∂δp_a = I,  ∂P_w/∂ρ = −R_a R_bc b / ρ²
//   ∂P_bk/∂δφ_k = [P_bk]×, ∂P_bk/∂δp_k = −R_kᵀ, ∂P_bk/∂P_w = R_kᵀ  (P_bk = R_kᵀ (P_w − p_k)),
//   ∂r/∂P_k = J_π (the camera model's), ∂P_k/∂P_bk = R_bcᵀ.
// A point the model cannot project (behind the camera) gives the constant residual
// (kOutOfView, kOutOfView) px with zero Jacobians: the robust kernel caps its cost and the
// solver is not pulled by it. Immutable; thread-safe.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "slamkit/core/factor.h"
#include "slamkit/factors/imu_state.h"
#include "slamkit/geometry/camera_models.h"

namespace slamkit {

class InverseDepthFactor final : public FactorN<2, ImuState, ImuState, Eigen::Matrix<double, 1, 1>> {
 public:
  static constexpr double kOutOfView = 1e3;
  using InverseDepth = Eigen::Matrix<double, 1, 1>;

  InverseDepthFactor(Key anchor, Key observer, Key inverse_depth, const Eigen::Vector3d& anchor_bearing,
                     const Eigen::Vector2d& measured, std::shared_ptr<const CameraModel> camera, const SE3& T_imu_cam,
                     std::shared_ptr<const NoiseModel> noise, std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({anchor, observer, inverse_depth}, std::move(noise), std::move(kernel)),
        bearing_(anchor_bearing.normalized()),
        measured_(measured),
        camera_(std::move(camera)),
        T_imu_cam_(T_imu_cam) {}

  Residual error(const ImuState& xa, const ImuState& xk, const InverseDepth& rho, Jacobian<ImuState>* J_a,
                 Jacobian<ImuState>* J_k, Jacobian<InverseDepth>* J_rho) const override;

  /// The feature in the world frame for anchor state xa and inverse depth ρ.
  Eigen::Vector3d world_point(const ImuState& xa, double rho) const;
  const Eigen::Vector2d& measured() const { return measured_; }

 private:
  Eigen::Vector3d bearing_;
  Eigen::Vector2d measured_;
  std::shared_ptr<const CameraModel> camera_;
  SE3 T_imu_cam_;
};

}  // namespace slamkit
