// Pose–landmark factors (g2o EDGE_SE2_XY, EDGE_SE3_TRACKXYZ): the landmark p observed in the
// sensor frame, e = (X · O)⁻¹ p − z, with O the sensor offset (identity in 2D).
#pragma once

#include "slamkit/core/factor.h"
#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

class PosePointFactor2 final : public FactorN<2, SE2, Eigen::Vector2d> {
 public:
  PosePointFactor2(Key pose, Key point, const Eigen::Vector2d& measured, std::shared_ptr<const NoiseModel> noise,
                   std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({pose, point}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const SE2& X, const Eigen::Vector2d& p, Jacobian<SE2>* J_X,
                 Jacobian<Eigen::Vector2d>* J_p) const override;

 private:
  Eigen::Vector2d measured_;
};

class PosePointFactor3 final : public FactorN<3, SE3, Eigen::Vector3d> {
 public:
  PosePointFactor3(Key pose, Key point, const Eigen::Vector3d& measured, const SE3& sensor_offset,
                   std::shared_ptr<const NoiseModel> noise, std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({pose, point}, std::move(noise), std::move(kernel)), measured_(measured), offset_(sensor_offset) {}
  Residual error(const SE3& X, const Eigen::Vector3d& p, Jacobian<SE3>* J_X,
                 Jacobian<Eigen::Vector3d>* J_p) const override;

 private:
  Eigen::Vector3d measured_;
  SE3 offset_;
};

}  // namespace slamkit
