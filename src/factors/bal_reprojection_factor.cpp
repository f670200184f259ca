#include "slamkit/factors/bal_reprojection_factor.h"

#include <Eigen/Geometry>

namespace slamkit {

BalCamera BalCamera::from_bal(const BalProblem::CameraParams& p) {
  BalCamera c;
  c.rotation = SO3::exp(p.head<3>());
  c.translation = p.segment<3>(3);
  c.f = p[6], c.k1 = p[7], c.k2 = p[8];
  return c;
}

BalProblem::CameraParams BalCamera::to_bal() const {
  BalProblem::CameraParams p;
  p.head<3>() = rotation.log();
  p.segment<3>(3) = translation;
  p[6] = f, p[7] = k1, p[8] = k2;
  return p;
}

BalReprojectionFactor::Residual BalReprojectionFactor::error(const BalCamera& c, const Eigen::Vector3d& X,
                                                             Jacobian<BalCamera>* J_camera,
                                                             Jacobian<Eigen::Vector3d>* J_point) const {
  return bal_reprojection(c.rotation.matrix(), c, X, measured_, J_camera, J_point);
}

}  // namespace slamkit
