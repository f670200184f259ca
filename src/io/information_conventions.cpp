#include "slamkit/io/information_conventions.h"

#include <cmath>

namespace slamkit {

Eigen::MatrixXd symmetric_from_upper_triangle(const double* values, int n) {
  Eigen::MatrixXd m(n, n);
  int k = 0;
  for (int r = 0; r < n; ++r) {
    for (int c = r; c < n; ++c) {
      m(r, c) = values[k];
      m(c, r) = values[k];
      ++k;
    }
  }
  return m;
}

namespace {
// T = diag(R(dθ), 1); returns Tᵀ Ω T (transpose = false) or T Ω Tᵀ (transpose = true, the inverse).
Eigen::Matrix3d rotate_xy(const Eigen::Matrix3d& omega, double dtheta, bool inverse) {
  Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
  const double c = std::cos(dtheta), s = std::sin(dtheta);
  T(0, 0) = c, T(0, 1) = -s, T(1, 0) = s, T(1, 1) = c;
  Eigen::Matrix3d out = inverse ? Eigen::Matrix3d(T * omega * T.transpose())
                                : Eigen::Matrix3d(T.transpose() * omega * T);
  // Keep the result exactly symmetric (the products above differ in the last ulp).
  return 0.5 * (out + out.transpose());
}

Eigen::MatrixXd scale_rotation_blocks(const Eigen::MatrixXd& omega, double cross, double rot) {
  Eigen::MatrixXd out = omega;
  out.topRightCorner(3, 3) *= cross;
  out.bottomLeftCorner(3, 3) *= cross;
  out.bottomRightCorner(3, 3) *= rot;
  return out;
}
}  // namespace

Eigen::Matrix3d toro2d_to_g2o_information(const Eigen::Matrix3d& omega_toro, double dtheta) {
  return rotate_xy(omega_toro, dtheta, false);
}

Eigen::Matrix3d g2o_to_toro2d_information(const Eigen::Matrix3d& omega_g2o, double dtheta) {
  return rotate_xy(omega_g2o, dtheta, true);
}

Eigen::MatrixXd rotation_vector_to_g2o_information(const Eigen::MatrixXd& omega) {
  return scale_rotation_blocks(omega, 2.0, 4.0);
}

Eigen::MatrixXd g2o_to_rotation_vector_information(const Eigen::MatrixXd& omega_g2o) {
  return scale_rotation_blocks(omega_g2o, 0.5, 0.25);
}

}  // namespace slamkit
