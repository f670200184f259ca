#include "slamkit/factors/pose_point_factor.h"

#include "slamkit/core/pose_graph_error.h"

namespace slamkit {

PosePointFactor2::Residual PosePointFactor2::error(const SE2& X, const Eigen::Vector2d& p, Jacobian<SE2>* J_X,
                                                   Jacobian<Eigen::Vector2d>* J_p) const {
  return pose2_point_error(measured_, X, p, J_X, J_p);
}

PosePointFactor3::Residual PosePointFactor3::error(const SE3& X, const Eigen::Vector3d& p, Jacobian<SE3>* J_X,
                                                   Jacobian<Eigen::Vector3d>* J_p) const {
  return pose3_point_error(measured_, X, offset_, p, J_X, J_p);
}

}  // namespace slamkit
