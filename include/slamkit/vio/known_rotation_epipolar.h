// The epipolar model with a known rotation (IMU-aided 2-point RANSAC; Troiani, Martinelli,
// Laugier, Scaramuzza, "2-Point-based Outlier Rejection for Camera-IMU Systems with Applications to
// Micro Aerial Vehicles", ICRA 2014; docs/frontend.md, session 28).
//
// Bearings b1 (frame 1) and b2 (frame 2) of a static point satisfy b2ᵀ [t]× R b1 = 0 with
// R = R_c2_c1 (x_c2 = R x_c1 + t). With R known (the gyroscope), write a = R b1 and
// n = a × b2: the constraint is t · n = 0, linear in t, so t has 2 degrees of freedom and two
// matches give it, t ∝ n × n' (up to sign, which the epipolar test does not see).
// The error of a match is the angle between b2 and the epipolar plane spanned by t and a:
//   sin ε = |b2 · (t × a)| / |t × a|;
// since a lies in that plane, ε ≤ ∠(b2, a) = the rotation residual. A match whose rotation residual
// is under the inlier angle is an inlier of every t: it says nothing about t ("uninformative").
// Pure rotation (translation too small to define t): when at least pure_rotation_share of the
// matches (or all but one) are uninformative, t is set to 0 and every match is judged by its
// rotation residual ∠(b2, R b1) alone (a crowd moving as one cannot then pass as "the" translation).
// Otherwise: 2-point RANSAC (samples among the informative matches, MSAC cost over all, adaptive
// number of iterations), t refit by least squares on the inliers (the smallest right singular
// vector of the rows nᵢ / |t × aᵢ|, re-weighted with the new t twice: the rows' residuals are then
// the sines), then optionally refined by Levenberg–Marquardt on the Cauchy loss of the sines over
// the matches under refine_angle, with R refined too under a prior ½|Log(R R₀ᵀ)|² / σ² when σ > 0.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace slamkit {

struct KnownRotationOptions {
  double inlier_angle_rad = 0.5 / 190.0;  ///< RANSAC inlier angle (and the "informative" cut)
  double confidence = 0.99;
  int max_iterations = 1000;
  int min_inliers = 8;                    ///< fewer RANSAC inliers: no consensus
  /// t is undefined (pure rotation) when at least this share of the matches is uninformative.
  double pure_rotation_share = 0.5;
  bool refit = true;                      ///< least-squares t on the RANSAC inliers
  bool refine = true;                     ///< LM on the Cauchy loss of the sines (see above)
  double refine_angle_rad = 1.0 / 190.0;  ///< the matches refined on: angle under this after the refit
  double cauchy_scale_rad = 0.5 / 190.0;  ///< c of the Cauchy loss
  /// σ of the prior on R in the refinement [rad]; 0: R held at the given rotation.
  double rotation_prior_sigma_rad = 0.0;
};

enum class KnownRotationStatus : std::uint8_t {
  kTranslation,      ///< t found by the 2-point RANSAC
  kPureRotation,     ///< t undefined: t = 0, matches judged by ∠(b2, R b1)
  kTooFewMatches,    ///< fewer than 2 usable (finite, non-zero) bearing pairs
  kInvalidRotation,  ///< R not finite or not a rotation (|RᵀR − I| > 1e-6 or det R < 0)
  kNoConsensus,      ///< fewer than min_inliers RANSAC inliers
};
const char* to_string(KnownRotationStatus s);

struct KnownRotationModel {
  KnownRotationStatus status = KnownRotationStatus::kTooFewMatches;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< R_c2_c1 (the given one, or refined under its prior)
  /// Unit translation direction (0 unless kTranslation), oriented by orient_translation: the static
  /// matches (within refine_angle_rad of their plane) lie ahead of R b1, i.e. at positive depth.
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  int usable = 0;        ///< finite, non-zero bearing pairs
  int informative = 0;   ///< usable pairs whose rotation residual exceeds the inlier angle
  int inliers = 0;       ///< usable pairs within the inlier angle of the final model
  int iterations = 0;    ///< RANSAC samples drawn
};

/// t ∝ (R a1 × b1') × (R a2 × b2') from two matches (a: frame-1 bearing, b: frame-2 bearing), unit;
/// false if degenerate (a match without parallax, or both on one epipolar plane) or not finite.
bool translation_from_two_matches(const Eigen::Matrix3d& R, const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                                  const Eigen::Vector3d& a2, const Eigen::Vector3d& b2, Eigen::Vector3d* t);

/// Angle [rad] between b2 and the epipolar plane of b1 under (R, t); with t = 0 (or b1 at the
/// epipole) the rotation residual ∠(b2, R b1). Bearings need not be unit; NaN if one is zero.
double known_rotation_angle(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& b1,
                            const Eigen::Vector3d& b2);

/// Cheirality (session 31): a static point at depth Z₁ > 0 is seen in frame 2 along Z₁ R b1 + s t
/// (s > 0 the translation's length), i.e. on the epipolar great circle between R b1 (Z₁ = ∞) and t
/// (Z₁ → 0). The signed angle [rad] from a = R b1 toward t along that circle, atan2(b2·u, b2·a) with u
/// the unit tangent at a toward t; negative means b2 lies on the far side of a, a negative depth
/// for a static point. 0 when t = 0 or a is at the epipole; NaN if a bearing is zero. A mover that slides
/// backwards along its epipolar line has a negative parallax while its distance to the plane is small.
double known_rotation_parallax(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& b1,
                               const Eigen::Vector3d& b2);

/// t or −t, whichever gives the matches within inlier_angle_rad of the epipolar plane a positive
/// parallax (above min_parallax_rad) in the majority: the 2-point solver's t is up to sign, the
/// static scene fixes it (fit_known_rotation returns its t so oriented). Ties keep t. Throws std::invalid_argument if the sizes differ.
Eigen::Vector3d orient_translation(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const std::vector<Eigen::Vector3d>& b1,
                                   const std::vector<Eigen::Vector3d>& b2, double inlier_angle_rad, double min_parallax_rad);

/// The model of the matches b1[i] → b2[i] under the rotation R = R_c2_c1 (see above). Non-finite or
/// zero bearings are skipped. Deterministic (fixed RANSAC seed). Never throws on data; throws
/// std::invalid_argument if b1 and b2 differ in size or an option is out of range.
KnownRotationModel fit_known_rotation(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                      const Eigen::Matrix3d& R, const KnownRotationOptions& options = {});

}  // namespace slamkit
