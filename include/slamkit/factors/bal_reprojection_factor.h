// The BAL camera as a manifold variable, and its reprojection factor.
//
// BalCamera: rotation R (SO3), translation t, focal length f, radial distortion k1, k2.
//   parameters (ambient, 10): [qx, qy, qz, qw, tx, ty, tz, f, k1, k2]
//   tangent (9):               [δφ, δt, δf, δk1, δk2],  R ⊞ δφ = R · Exp(δφ), the rest additive.
// BalReprojectionFactor: r = u(camera, X) − z with the BAL model (core/bal_problem.h):
//   P = R X + t,  p = −P/P_z,  n = |p|²,  d = 1 + k1 n + k2 n²,  u = f d p.
// Analytic Jacobians (right perturbation of R):
//   ∂P/∂δφ = −R [X]×,  ∂P/∂t = I,  ∂P/∂X = R,
//   ∂p/∂P = [−1/P_z, 0, P_x/P_z²; 0, −1/P_z, P_y/P_z²],
//   ∂u/∂p = f (d I + 2 (k1 + 2 k2 n) p pᵀ),  ∂u/∂f = d p,  ∂u/∂k1 = f n p,  ∂u/∂k2 = f n² p.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "slamkit/core/bal_problem.h"
#include "slamkit/core/factor.h"
#include "slamkit/geometry/so3.h"

namespace slamkit {

struct BalCamera {
  using Tangent = Eigen::Matrix<double, 9, 1>;
  SO3 rotation;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double f = 1.0, k1 = 0.0, k2 = 0.0;

  BalCamera plus(const Tangent& d) const {
    BalCamera c;
    c.rotation = rotation.plus(d.head<3>());
    c.translation = translation + d.segment<3>(3);
    c.f = f + d[6], c.k1 = k1 + d[7], c.k2 = k2 + d[8];
    return c;
  }
  /// From / to the 9 BAL parameters (angle-axis rotation).
  static BalCamera from_bal(const BalProblem::CameraParams& p);
  BalProblem::CameraParams to_bal() const;
};

template <>
struct ManifoldTraits<BalCamera> {
  static constexpr int kAmbient = 10, kTangent = 9;
  static const char* name() { return "BalCamera"; }
  static void to_params(const BalCamera& c, double* p) {
    Eigen::Map<Eigen::Vector4d> q(p);
    Eigen::Map<Eigen::Vector3d> t(p + 4);
    q = c.rotation.quaternion().coeffs();
    t = c.translation;
    p[7] = c.f, p[8] = c.k1, p[9] = c.k2;
  }
  static BalCamera from_params(const double* p) {
    BalCamera c;
    c.rotation = SO3(Eigen::Quaterniond(Eigen::Map<const Eigen::Vector4d>(p)));
    c.translation = Eigen::Map<const Eigen::Vector3d>(p + 4);
    c.f = p[7], c.k1 = p[8], c.k2 = p[9];
    return c;
  }
};

/// The BAL residual r = u(camera, X) − z and (optional) its Jacobians, for a camera whose
/// rotation matrix R is given (computed once per camera by the bundle-adjustment solver).
/// Fixed-size, no allocation: the kernel of BalReprojectionFactor and of BalNormalEquations.
inline Eigen::Vector2d bal_reprojection(const Eigen::Matrix3d& R, const BalCamera& c, const Eigen::Vector3d& X,
                                        const Eigen::Vector2d& z, Eigen::Matrix<double, 2, 9>* J_camera,
                                        Eigen::Matrix<double, 2, 3>* J_point) {
  const Eigen::Vector3d P = R * X + c.translation;
  const double iz = 1.0 / P.z();
  const Eigen::Vector2d p(-P.x() * iz, -P.y() * iz);
  const double n = p.squaredNorm();
  const double d = 1.0 + c.k1 * n + c.k2 * n * n;
  const Eigen::Vector2d r = c.f * d * p - z;
  if (!J_camera && !J_point) return r;
  // du/dP = du/dp · dp/dP (2×3).
  const double dd_dn = c.k1 + 2.0 * c.k2 * n;
  const Eigen::Matrix2d du_dp = (c.f * d) * Eigen::Matrix2d::Identity() + (2.0 * c.f * dd_dn) * p * p.transpose();
  Eigen::Matrix<double, 2, 3> dp_dP;
  dp_dP << -iz, 0.0, P.x() * iz * iz, 0.0, -iz, P.y() * iz * iz;
  const Eigen::Matrix<double, 2, 3> du_dP = du_dp * dp_dP;
  const Eigen::Matrix<double, 2, 3> du_dR = du_dP * R;  // = ∂u/∂X
  if (J_point) *J_point = du_dR;
  if (J_camera) {
    // ∂P/∂δφ = −R [X]×, so ∂u/∂δφ = −(∂u/∂X) [X]×.
    Eigen::Matrix3d X_hat;
    X_hat << 0.0, -X.z(), X.y(), X.z(), 0.0, -X.x(), -X.y(), X.x(), 0.0;
    J_camera->leftCols<3>() = -du_dR * X_hat;
    J_camera->middleCols<3>(3) = du_dP;
    J_camera->col(6) = d * p;
    J_camera->col(7) = c.f * n * p;
    J_camera->col(8) = c.f * n * n * p;
  }
  return r;
}

class BalReprojectionFactor final : public FactorN<2, BalCamera, Eigen::Vector3d> {
 public:
  BalReprojectionFactor(Key camera, Key point, const Eigen::Vector2d& measured,
                        std::shared_ptr<const NoiseModel> noise = nullptr,
                        std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({camera, point}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const BalCamera& camera, const Eigen::Vector3d& X, Jacobian<BalCamera>* J_camera,
                 Jacobian<Eigen::Vector3d>* J_point) const override;
  const Eigen::Vector2d& measured() const { return measured_; }

 private:
  Eigen::Vector2d measured_;
};

}  // namespace slamkit
