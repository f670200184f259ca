// Small 2D helpers shared by the relaxers' inner loops (chain SGD, tree relaxation).
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace slamkit::detail {

inline constexpr double kPi2D = 3.14159265358979323846;

/// Angle into [−π, π) without trigonometry (the residuals are wrapped in every update).
inline double wrap_angle(double a) {
  if (a >= -kPi2D && a < kPi2D) return a;
  return a - 2 * kPi2D * std::floor((a + kPi2D) / (2 * kPi2D));
}

/// R = (c −s; s c).
inline Eigen::Matrix2d rot2(double c, double s) {
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}

/// W = G Ω Gᵀ, G = blockdiag(R, 1): the information Ω rotated into the global frame.
inline Eigen::Matrix3d rotate_information(const Eigen::Matrix3d& info, double c, double s) {
  Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
  G.topLeftCorner<2, 2>() = rot2(c, s);
  return G * info * G.transpose();
}

}  // namespace slamkit::detail
