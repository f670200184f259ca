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

/// One camera as the fused kernel reads it, formed once per camera per pass: R row-major, t, f, k1, k2
/// (16 doubles with the padding: the point pass loads four frames as 4×4 blocks).
struct BalCameraFrame {
  double R[9], t[3], f, k1, k2, padding = 0.0;
  static BalCameraFrame from(const BalCamera& c) {
    BalCameraFrame fr;
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(fr.R) = c.rotation.matrix();
    fr.t[0] = c.translation.x(), fr.t[1] = c.translation.y(), fr.t[2] = c.translation.z();
    fr.f = c.f, fr.k1 = c.k1, fr.k2 = c.k2;
    return fr;
  }
};

/// The projection both kernels share: P = R X + t, p = −P/P_z (iz = 1/P_z), n = |p|²,
/// d = 1 + k1 n + k2 n² (the radial factor), fd = f d; u = fd p.
/// T is double, or a GCC vector of doubles (several observations of one camera, one per lane):
/// the same operations in the same order, elementwise IEEE, so every lane gets the bits the
/// scalar code gives (no FMA contraction: the build is ISO C++, -ffp-contract=off).
template <class T>
struct BalProjectionT {
  T iz, p0, p1, n, d, fd;
};
using BalProjection = BalProjectionT<double>;

/// Cam: BalCameraFrame, or a frame whose fields are vectors too (lanes of different cameras).
template <class Cam, class T>
inline BalProjectionT<T> bal_project(const Cam& c, const T* X) {
  const T P0 = c.R[0] * X[0] + c.R[1] * X[1] + c.R[2] * X[2] + c.t[0];
  const T P1 = c.R[3] * X[0] + c.R[4] * X[1] + c.R[5] * X[2] + c.t[1];
  const T P2 = c.R[6] * X[0] + c.R[7] * X[1] + c.R[8] * X[2] + c.t[2];
  BalProjectionT<T> q;
  q.iz = 1.0 / P2;
  q.p0 = -P0 * q.iz, q.p1 = -P1 * q.iz;
  q.n = q.p0 * q.p0 + q.p1 * q.p1;
  q.d = 1.0 + q.n * (c.k1 + c.k2 * q.n);
  q.fd = c.f * q.d;
  return q;
}

/// The BAL residual only: r = u − z (the cost pass).
inline void bal_residual(const BalCameraFrame& c, const double* X, const double* z, double* r) {
  const BalProjection q = bal_project(c, X);
  r[0] = q.fd * q.p0 - z[0], r[1] = q.fd * q.p1 - z[1];
}

/// Fused residual and Jacobians, the same math as bal_reprojection with the shared
/// sub-expressions written out (no temporaries beyond scalars, no allocation):
///   A = ∂u/∂p = f d I + s p pᵀ (s = 2 f (k1 + 2 k2 n)),  T = ∂u/∂P = A ∂p/∂P = −(1/P_z) [A | A p],
///   E = ∂u/∂X = T R,  rotation columns of F: row k = X × E_k (= −E_k [X]×),  F's t columns = T,
///   F's intrinsic columns: d p, f n p, f n² p.
/// Out: r (2), E (2×3 row-major), F (2×9 row-major, i.e. Fᵀ column-major 9×2). Cam, V as above.
template <class Cam, class V>
inline void bal_linearize(const Cam& c, const V* X, const V* z, V* r, V* E, V* F) {
  const BalProjectionT<V> q = bal_project(c, X);
  const V iz = q.iz, p0 = q.p0, p1 = q.p1, n = q.n, d = q.d, fd = q.fd;
  r[0] = fd * p0 - z[0], r[1] = fd * p1 - z[1];
  const V s = 2.0 * c.f * (c.k1 + 2.0 * c.k2 * n);
  const V a = fd + s * p0 * p0, b = s * p0 * p1, cc = fd + s * p1 * p1;
  const V m = -iz;
  // T rows (∂u/∂P).
  const V T0 = m * a, T1 = m * b, T2 = m * (a * p0 + b * p1);
  const V U0 = m * b, U1 = m * cc, U2 = m * (b * p0 + cc * p1);
  for (int k = 0; k < 3; ++k) {
    E[k] = T0 * c.R[k] + T1 * c.R[3 + k] + T2 * c.R[6 + k];
    E[3 + k] = U0 * c.R[k] + U1 * c.R[3 + k] + U2 * c.R[6 + k];
  }
  for (int row = 0; row < 2; ++row) {
    const V* e = E + 3 * row;
    V* Fr = F + 9 * row;
    Fr[0] = X[1] * e[2] - X[2] * e[1];
    Fr[1] = X[2] * e[0] - X[0] * e[2];
    Fr[2] = X[0] * e[1] - X[1] * e[0];
  }
  F[3] = T0, F[4] = T1, F[5] = T2, F[12] = U0, F[13] = U1, F[14] = U2;
  const V fn = c.f * n, fnn = fn * n;
  F[6] = d * p0, F[7] = fn * p0, F[8] = fnn * p0;
  F[15] = d * p1, F[16] = fn * p1, F[17] = fnn * p1;
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
