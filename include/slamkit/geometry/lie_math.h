// Shared small helpers for the Lie groups: skew matrices and the trigonometric
// coefficients of the SO(3) Jacobians, each with a Taylor branch near θ = 0 so that
// no expression divides by a vanishing angle.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace slamkit {

constexpr double kPi = 3.14159265358979323846;

// Below this angle the closed forms lose digits; the Taylor branches take over.
// With θ < 1e-4 the first omitted Taylor term is below 1e-16 relative.
constexpr double kSmallAngle = 1e-4;

/// [v]×, so that [v]× w = v × w.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// Inverse of skew(): the vector of the skew-symmetric part of m.
inline Eigen::Vector3d unskew(const Eigen::Matrix3d& m) {
  return 0.5 * Eigen::Vector3d(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

/// Wraps an angle to (−π, π].
inline double wrap_angle(double a) {
  if (a > -kPi && a <= kPi) return a;
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

namespace lie_detail {

// Each coefficient below is a closed form that cancels catastrophically near θ = 0
// (relative error ≈ c·ε/θ^k). Below a cutoff we switch to its Taylor series in θ², with
// enough terms that truncation stays below 1e-16; the cutoffs balance the two errors.

/// Σ c_k x^k (Horner).
template <int N>
inline double poly(double x, const double (&c)[N]) {
  double r = c[N - 1];
  for (int k = N - 2; k >= 0; --k) r = r * x + c[k];
  return r;
}

/// sin θ / θ (no cancellation; the series only avoids 0/0).
inline double sinc(double t) {
  return std::abs(t) < kSmallAngle ? 1.0 - t * t / 6.0 + t * t * t * t / 120.0 : std::sin(t) / t;
}
/// (1 − cos θ) / θ² = ½ sinc²(θ/2), exact without cancellation.
inline double one_minus_cos_over_t2(double t) {
  const double s = sinc(0.5 * t);
  return 0.5 * s * s;
}
/// (θ − sin θ) / θ³
inline double t_minus_sin_over_t3(double t) {
  static constexpr double c[] = {1.0 / 6, -1.0 / 120, 1.0 / 5040, -1.0 / 362880, 1.0 / 39916800,
                                 -1.0 / 6227020800.0};
  return std::abs(t) < 0.5 ? poly(t * t, c) : (t - std::sin(t)) / (t * t * t);
}
/// (θ² + 2 cos θ − 2) / (2 θ⁴)
inline double se3_q_coefficient2(double t) {
  static constexpr double c[] = {1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800, 1.0 / 479001600,
                                 -1.0 / 87178291200.0};
  if (std::abs(t) < 0.5) return poly(t * t, c);
  const double t2 = t * t;
  return (t2 + 2.0 * std::cos(t) - 2.0) / (2.0 * t2 * t2);
}
/// (2θ − 3 sin θ + θ cos θ) / (2 θ⁵)
inline double se3_q_coefficient3(double t) {
  static constexpr double c[] = {1.0 / 120,          -1.0 / 2520,          1.0 / 120960,
                                 -1.0 / 9979200,     1.0 / 1245404160.0,   -1.0 / 217945728000.0,
                                 1.0 / 51011754393600.0};
  if (std::abs(t) < 1.0) return poly(t * t, c);
  const double t2 = t * t;
  return (2.0 * t - 3.0 * std::sin(t) + t * std::cos(t)) / (2.0 * t2 * t2 * t);
}
/// 1/θ² − (1 + cos θ) / (2 θ sin θ): the [φ]×² coefficient of Jr⁻¹ and Jl⁻¹. The form
/// with cot(θ/2) stays finite at θ = π (where sin θ = 0 but 1 + cos θ = 0 as well).
inline double jinv_coefficient(double t) {
  static constexpr double c[] = {1.0 / 12, 1.0 / 720, 1.0 / 30240, 1.0 / 1209600, 1.0 / 47900160,
                                 691.0 / 1307674368000.0};
  if (std::abs(t) < 0.5) return poly(t * t, c);
  const double half = 0.5 * t;
  return 1.0 / (t * t) - std::cos(half) / (2.0 * t * std::sin(half));
}

}  // namespace lie_detail
}  // namespace slamkit
