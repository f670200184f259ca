// Dynamic-feature detector of DVI-SLAM (P4 algorithm 1, second half; docs/frontend.md).
// Input: the pixels of the features matched between two frames (point tracks; no image needed,
// so the feature-level simulator can use it too). Steps:
//   1. undistort: every pixel is unprojected with the camera model to a bearing (x, y, z) and
//      re-projected into a virtual pinhole with the same fx, fy, cx, cy: u = fx·x/z + cx, so
//      distances stay in pixels (no camera: the pixels are taken as undistorted already);
//      pixels that cannot be unprojected, or bearings with z ≤ min_bearing_z, are "unknown";
//   2. a camera that does not move: if the median flow |p2 − p1| is below static_camera_flow_px,
//      F is undefined (all static points have zero flow); each feature is then judged by its
//      flow relative to the dominant (median) flow: |f_i − median(f)| > threshold ⇒ dynamic;
//   3. otherwise F by the normalized 8-point algorithm inside RANSAC (cv::findFundamentalMat,
//      FM_RANSAC), refit by the 8-point least squares on all RANSAC inliers, and for every match the epipolar line l = F p1 = (X, Y, Z) and distance
//      d = |p2ᵀ F p1| / √(X² + Y²), mapped back to image pixels through the local Jacobian J of
//      the undistortion at p2 (d_img = d / |Jᵀ n|, n the line's unit normal; J = I for a pinhole)
//      so that the threshold means the same at the centre and at the rim of a fisheye image;
//      d_img > threshold_px ⇒ dynamic, else static;
//   4. M = static / (static + dynamic) of the frame.
// With a trusted subset (classify's third argument, e.g. the tracks static in their last test)
// the motion model of step 3 is fitted on it alone and every match is tested against it; on
// bearings E is refined by robust least squares after the linear refit (see the options).
// Fewer than min_matches usable matches, or a RANSAC that finds no F, is a handled condition:
// every feature is "unknown", M = 1 (nothing is known to move), and the status says why.
#pragma once

#include <algorithm>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/geometry/camera_models.h"

namespace slamkit {

enum class FeatureMotion : std::uint8_t { kUnknown = 0, kStatic = 1, kDynamic = 2 };
const char* to_string(FeatureMotion m);

enum class ClassificationStatus : std::uint8_t {
  kEpipolar,       ///< classified by the epipolar distance to a RANSAC F
  kStaticCamera,   ///< the camera did not move: classified by flow relative to the median flow
  kTooFewMatches,  ///< fewer than min_matches usable matches: all unknown
  kNoFundamental,  ///< RANSAC returned no F (degenerate configuration): all unknown
};
const char* to_string(ClassificationStatus s);

struct DynamicFilterOptions {
  double threshold_px = 1.0;          ///< d > threshold ⇒ dynamic (P4: 1 px)
  double ransac_threshold_px = 0.5;   ///< RANSAC inlier distance to the epipolar line (virtual pinhole px)
  double ransac_confidence = 0.99;
  int ransac_max_iterations = 1000;
  bool refit_on_inliers = true;       ///< refit F by the 8-point least squares on the RANSAC inliers
  int min_matches = 8;                ///< the 8-point algorithm's minimum
  double static_camera_flow_px = 0.5;  ///< median flow below this ⇒ camera static (step 2); < 0 disables
  double min_bearing_z = 0.1;         ///< fisheye bearings closer to the image plane are unknown
  /// Non-pinhole camera: estimate the essential matrix on the unit bearings (8-point in RANSAC,
  /// seeded, refit on the inliers) and score the angle between b2 and the epipolar plane of b1,
  /// times fx, in pixels, instead of F on the virtual pinhole (whose rim magnification, 1/cos²θ,
  /// lets the rim points either leave the RANSAC or dominate the fit; docs/frontend.md).
  bool spherical = true;
  /// With a trusted subset given to classify(): the camera's motion (F, or E and the rotation) is
  /// fitted on the trusted matches alone when at least this many are usable, then every match is
  /// tested against it; fewer: fitted on all. A crowd moving as one (a queue of walkers) can hold
  /// more matches than the background and win the RANSAC on all matches (docs/frontend.md,
  /// session 25); tracks that were static in their last test cannot be that crowd's.
  int min_trusted_matches = 16;
  /// Matches a subset needs for the model to be fitted on it alone: max(min_matches, min_trusted_matches).
  int min_subset_fit() const { return std::max(min_matches, min_trusted_matches); }
  /// Spherical mode: refine E = [t]× R after the linear refit by Levenberg–Marquardt on the
  /// matches it was fitted on, minimizing Σ ρ(s_i), s_i = b2·(t × R b1) / |t × R b1| (the sine of
  /// the angle between b2 and the epipolar plane), ρ the Cauchy loss at ransac_threshold_px / fx.
  /// The linear 8-point minimizes an algebraic error that weighs the matches unequally.
  bool refine_essential = true;
  /// IMU-aided model (session 28, vio/known_rotation_epipolar.h): when classify() is given the
  /// rotation R_c2_c1 between the two frames (e.g. the integrated gyroscope), only the translation
  /// direction is fitted (2-point RANSAC on the bearings, least-squares refit, and with
  /// refine_essential an LM refinement), instead of E or F; the distance and threshold are as above.
  /// Needs a camera model; else, or if R is unusable or finds no consensus, the estimated model is used
  /// (Classification::motion_model says which). On by default: it acts only when a rotation is given
  /// (`slamkit vio --images` gives the gyroscope's; `slamkit frontend` has none). On the rendered rooms
  /// it raised precision and recall in every room and cut the classification time ~10× (docs/frontend.md, session 28).
  bool known_rotation = true;
  /// With known_rotation and refine_essential: σ [rad] of the prior that lets the refinement move R
  /// (a gyro bias error); 0 holds R at the given rotation.
  double rotation_prior_sigma_rad = 0.0;
  /// With known_rotation: the translation is undefined (pure rotation; every match judged by
  /// ∠(b2, R b1)) when at least this share of the fitted matches moves as R alone says.
  double pure_rotation_share = 0.5;
  /// With known_rotation (a translation found, not pure rotation): also flag a match whose bearing lies
  /// behind R b1 on its epipolar circle, i.e. a negative depth for a static point, by more than the
  /// threshold (f · the angle, known_rotation_parallax; t's sign from the fitted matches). It catches
  /// movers that slide backwards along their epipolar line, which the distance to the plane cannot see
  /// (docs/frontend.md, session 31). The reported distance is the larger of the two.
  bool cheirality = true;
};

/// Which camera-motion model classified the matches (status kEpipolar).
enum class MotionModel : std::uint8_t {
  kEstimated,         ///< E (bearings) or F (pinhole) fitted from the tracks alone
  kKnownRotation,     ///< the given rotation, the translation direction by 2-point RANSAC
  kPureRotation,      ///< the given rotation, translation undefined: distance = f·∠(b2, R b1)
  kRotationRejected,  ///< a rotation was given but not usable (not a rotation, no camera model, no consensus): estimated
};
const char* to_string(MotionModel m);

struct Classification {
  std::vector<FeatureMotion> flags;  ///< one per input match
  std::vector<double> distance_px;   ///< d (epipolar) or the flow residual (static camera); NaN if unknown
  double static_ratio = 1.0;         ///< M = static / (static + dynamic); 1 when nothing is classified
  int n_static = 0, n_dynamic = 0, n_unknown = 0;
  double median_flow_px = 0.0;       ///< median |p2 − p1| of the undistorted matches
  ClassificationStatus status = ClassificationStatus::kTooFewMatches;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();  ///< p2ᵀ F p1 = 0 on the virtual pinhole (kEpipolar)
  MotionModel motion_model = MotionModel::kEstimated;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< R_c2_c1 of kKnownRotation / kPureRotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      ///< unit t of kKnownRotation (0 otherwise)
};

class DynamicFeatureFilter {
 public:
  /// camera: the model of the images (nullptr: pixels are undistorted pinhole already).
  /// Throws std::invalid_argument on bad options.
  explicit DynamicFeatureFilter(DynamicFilterOptions options = {}, std::shared_ptr<const CameraModel> camera = nullptr);
  /// Classifies the matches prev[i] → cur[i] (pixels of two frames). Throws std::invalid_argument
  /// if the sizes differ; non-finite pixels are unknown.
  /// trusted (optional, one per match): the matches the motion model is fitted on (see
  /// min_trusted_matches); its size must be that of prev if given.
  /// R_c2_c1 (optional): the camera's rotation from frame 1 (prev) to frame 2 (cur), x_c2 = R x_c1 + t;
  /// used with options().known_rotation (see there).
  Classification classify(const std::vector<Eigen::Vector2d>& prev, const std::vector<Eigen::Vector2d>& cur,
                          const std::vector<char>* trusted = nullptr, const Eigen::Matrix3d* R_c2_c1 = nullptr) const;
  /// Trust contest: c is classify()'s result with a trusted subset. The model fitted on the matches
  /// c flags (at least max(min_matches, min_trusted_matches) of them) replaces c when it passes
  /// more than `ratio` times as many matches as static; returns whether it did. A trusted set that
  /// one rigid mover has captured flags the static scene, which agrees on a model of its own.
  bool contest(const std::vector<Eigen::Vector2d>& prev, const std::vector<Eigen::Vector2d>& cur,
               const Eigen::Matrix3d* R_c2_c1, double ratio, Classification* c) const;
  /// The virtual-pinhole pixel of a raw pixel (step 1); false if it cannot be undistorted.
  bool undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* out) const;
  /// The raw pixel of a virtual-pinhole pixel (the inverse of undistort); false if the camera
  /// cannot project it.
  bool distort(const Eigen::Vector2d& virtual_uv, Eigen::Vector2d* out) const;
  /// The epipolar distance (px) classify() gives the match raw1 → raw2 under c's model (status
  /// kEpipolar; in spherical mode the epipolar angle · fx, without the pure-rotation alternative);
  /// NaN if c has no model or a pixel cannot be undistorted.
  double epipolar_distance(const Classification& c, const Eigen::Vector2d& raw1, const Eigen::Vector2d& raw2) const;
  /// The point of raw1's epipolar line l = F p1 (virtual pinhole) nearest raw2's virtual pixel,
  /// moved by offset_px along the line, as a raw pixel; false if c has no model or a pixel cannot
  /// be mapped.
  bool epipolar_point(const Classification& c, const Eigen::Vector2d& raw1, const Eigen::Vector2d& raw2,
                      double offset_px, Eigen::Vector2d* raw_on_line) const;
  const DynamicFilterOptions& options() const { return options_; }

 private:
  /// ∂(virtual pixel)/∂(raw pixel) at uv by central differences; false for a pinhole (J = I).
  bool undistort_jacobian(const Eigen::Vector2d& uv, Eigen::Matrix2d* J) const;
  /// Step 3's pinhole distance: |b·l| / |l_xy| with l = F a (a, b virtual pixels), mapped to
  /// image pixels at raw2 through the undistortion's Jacobian.
  double pinhole_distance(const Eigen::Matrix3d& F, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                          const Eigen::Vector2d& raw2) const;
  bool spherical() const;
  /// Step 3 on bearings (spherical): fills c's distances, flags, F; false if no model was found.
  /// The model is fitted on the matches with fit[k] != 0.
  bool classify_spherical(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                          const std::vector<std::size_t>& index, const std::vector<char>& fit, Classification* c) const;
  /// Step 3 with a known rotation: fills c (distances, flags, F, R, t, motion_model) and returns true,
  /// or returns false (c.motion_model = kRotationRejected) to let the estimated model run.
  bool classify_known_rotation(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                               const std::vector<Eigen::Vector2d>& v1, const std::vector<Eigen::Vector2d>& v2,
                               const std::vector<Eigen::Vector2d>& raw2, const std::vector<std::size_t>& index,
                               const std::vector<char>& fit, const Eigen::Matrix3d& R, Classification* c) const;
  /// Pinhole-mode distance of the pure-rotation model: |J⁻¹ (b − π(R b1))| (virtual pixels to raw).
  double rotation_distance(const Eigen::Matrix3d& R, const Eigen::Vector3d& b1, const Eigen::Vector2d& b,
                           const Eigen::Vector2d& raw2) const;
  DynamicFilterOptions options_;
  std::shared_ptr<const CameraModel> camera_;
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
};

}  // namespace slamkit
