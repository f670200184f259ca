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
  const Eigen::Matrix3d R = c.rotation.matrix();
  const Eigen::Vector3d RX = R * X;
  const Eigen::Vector3d P = RX + c.translation;
  const double iz = 1.0 / P.z();
  const Eigen::Vector2d p(-P.x() * iz, -P.y() * iz);
  const double n = p.squaredNorm();
  const double d = 1.0 + c.k1 * n + c.k2 * n * n;
  const Residual r = c.f * d * p - measured_;
  if (!J_camera && !J_point) return r;

  // du/dP = du/dp · dp/dP (2×3).
  const double dd_dn = c.k1 + 2.0 * c.k2 * n;
  Eigen::Matrix2d du_dp = (c.f * d) * Eigen::Matrix2d::Identity() + (2.0 * c.f * dd_dn) * p * p.transpose();
  Eigen::Matrix<double, 2, 3> dp_dP;
  dp_dP << -iz, 0.0, P.x() * iz * iz, 0.0, -iz, P.y() * iz * iz;
  const Eigen::Matrix<double, 2, 3> du_dP = du_dp * dp_dP;
  if (J_point) *J_point = du_dP * R;
  if (J_camera) {
    // ∂P/∂δφ = −R [X]× = −[RX]× R.
    Eigen::Matrix3d X_hat;
    X_hat << 0.0, -X.z(), X.y(), X.z(), 0.0, -X.x(), -X.y(), X.x(), 0.0;
    const Eigen::Matrix<double, 2, 3> du_dR = du_dP * R;
    J_camera->leftCols<3>() = -du_dR * X_hat;
    J_camera->middleCols<3>(3) = du_dP;
    J_camera->col(6) = d * p;
    J_camera->col(7) = c.f * n * p;
    J_camera->col(8) = c.f * n * n * p;
  }
  return r;
}

}  // namespace slamkit
