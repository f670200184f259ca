// ImageFrontend: the DVI front end on a stream of images (docs/frontend.md, "Long baseline"):
// FeatureTracker (detection, KLT) then DynamicFeatureFilter over a longer baseline than one frame.
//
// Why: the epipolar distance of a moving point grows with the time between the two frames it is
// measured on. At 20 Hz with the TUM-VI fisheye (f ≈ 191 px) a person 4 m away walking 0.3 m/s
// moves 0.7 px per frame, under the 1 px threshold; over k frames it moves k times as far while
// the static points' distance stays at the tracking noise.
// Per frame t, a feature alive since frame t − a (age a ≥ k) is classified on the baseline k: the
// matches (p_{t−k}, p_t) of all tracks alive over k frames give F_k by RANSAC; younger features
// (0 < a < k) take their flag from the frame-to-frame test (F_1 on all tracked features), so
// two filter runs per frame at most (with every b in 1..k the classification cost grew k-fold).
// Multi-frame consistency with hysteresis: each track keeps the outcomes of its last n =
// consistency_checks epipolar tests (d > threshold or not). A static track becomes dynamic when
// at least consistency_hits of them exceed the threshold; a dynamic one stays dynamic while at
// least one of them does (it returns to static after n tests under the threshold). A static point
// whose distance crosses the threshold once by noise or a KLT slip stays static; a mover exceeds
// it test after test, and a mover's test dipping under the threshold once does not unflag it.
// consistency_checks = consistency_hits = 1 is the single-test rule.
// New features (age 0) are unknown. With sticky_dynamic a track once flagged dynamic stays so
// (moving objects rarely stop; a flag lost at a short baseline is not a change of motion).
// The threshold grows with the baseline b as b^baseline_threshold_exponent (√b by default).
// Appearance over the baseline: a tested track whose patch at t (about p_t) and at t − b (about
// p_{t−b}, in frame t − b) correlate below min_patch_ncc_baseline (zero-mean NCC) is rejected
// (dropped from the tracker, not in the result): a corner that is no 3D surface point (a T-junction
// of surfaces at different depths, an occlusion edge, a walker's silhouette) changes its patch as
// the background slides behind the edge, while a surface point, static or on a rigid mover, keeps it.
// Its epipolar distance is not a point's motion, so neither flag would be right.
// Trusted tracks (trusted_model): the camera's motion of each test is fitted on the tracks whose
// last test was static (DynamicFilterOptions::min_trusted_matches), so that a crowd moving as one,
// whose tracks are new or flagged, cannot take over the RANSAC.
// Trust contest (trust_contest_ratio, trust_contest_frames): after a cold start (a test with too few
// trusted tracks, fitted on all: the start, or tracks lost behind a walker covering the camera) the
// first trusted set may be one rigid mover's. While the trust is young, the model fitted on the tracks
// the trusted model flags replaces it when it passes more than ratio × as many matches
// (DynamicFeatureFilter::contest); the next frame's trust follows the new flags.
// Young trust needs a majority (young_trust_majority, session 38): while the contest may still run,
// a frame whose static features do not outnumber its flags by trust_contest_ratio claims no mover:
// its flags are isolated (left out of the estimator, not counted as dynamic). A young trusted set
// may itself be one mover's (the contest hands it over only once the other side is that much
// larger), so until one side is that much larger the frame cannot tell which side moves.
// A confirmed mover's dip (mover_grace_claims, session 39): a track claimed as a mover (flagged, not
// isolated) in each of its last n frames keeps its flag through one test under the threshold
// (FrontendFeature::graced). A walker's epipolar distance dips whenever its motion runs along the
// epipolar line for a frame; a static track flagged by noise or a slip is rarely claimed n times running.
// The graced flag is a flag like any other (the group rules apply); it does not extend the run, so
// the next dip needs n claims of the track's own.
// Epipolar re-search (epipolar_search): each test's dynamic flags are re-searched along the
// epipolar line in that test's frame pair; a re-found feature is static and its track moves.
// Affine re-alignment (affine_realign): each test's dynamic flags get their patch of frame t − b
// aligned with frame t under an affine warp (feature_affine_realign.h); the track moves to the
// aligned pixel, and the flag turns static if that pixel lies on the epipolar line; then the model is
// fitted again with those tracks trusted, and what it flags is re-aligned in turn (refit_model).
// IMU-aided model (filter.known_rotation, session 28): process() may be given the camera's rotation
// since the previous frame (e.g. from the gyroscope); a test over b frames is given the product of
// the last b of them (none if one is missing) and fits only the translation direction.
// Dynamic groups (groups): a flag with no other flag near it, or with fewer than two on a track whose
// last two tests were static (turned), is isolated (dynamic_groups.h): its motion stays kDynamic
// (the estimator leaves it out) but it is not counted as dynamic.
// M = static / (static + dynamic + isolated) over the classified features of the frame.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/dynamic_groups.h"
#include "slamkit/vio/feature_affine_realign.h"
#include "slamkit/vio/feature_epipolar_search.h"
#include "slamkit/vio/feature_tracker.h"

namespace slamkit {

/// The image front end's test: P4's 1 px threshold lowered to 0.9 px (session 35: with the affine
/// re-alignment removing most static track errors, 0.9 px keeps the 2–6 m recall above 0.8 on the
/// rendered rooms; docs/frontend.md). `slamkit frontend` (frame to frame) keeps 1 px.
inline DynamicFilterOptions image_frontend_filter() {
  DynamicFilterOptions f;
  f.threshold_px = 0.9;
  return f;
}

struct ImageFrontendOptions {
  FeatureTrackerOptions tracker;
  DynamicFilterOptions filter = image_frontend_filter();
  int baseline_frames = 4;      ///< k: the longest baseline of the epipolar test (1: frame to frame)
  bool sticky_dynamic = false;  ///< a track flagged dynamic once stays dynamic (measured: worse precision)
  /// The test on baseline b uses threshold_px · b^e: a mover's epipolar distance grows like b, the
  /// KLT drift of a static track like √b (a random walk), so e = 0.5 keeps the false-alarm rate of
  /// the long baseline near the frame-to-frame one; e = 0: the same threshold on every baseline.
  double baseline_threshold_exponent = 0.5;
  /// Consistency rule (see above). Default 1 of 1 (the single test): on rooms 1–4 (high, 20 s)
  /// 2 of 3 with hysteresis raised precision by ≤ 0.015 and cut recall by 0.05–0.08 (docs/frontend.md).
  int consistency_checks = 1;   ///< n: the last n epipolar tests of a track are kept (1..16)
  int consistency_hits = 1;     ///< dynamic iff ≥ this many of them exceed the threshold (1..n)
  /// Appearance check over the tested baseline (see above); ≤ -1 disables it. The patch half size
  /// is tracker.patch_half_px.
  double min_patch_ncc_baseline = -1.0;
  /// Appearance against the track's first frame: a track whose patch now (about p_t) and at its
  /// detection correlate below this (zero-mean NCC, half size tracker.patch_half_px) is rejected like
  /// the check above: a track that slid from the background onto a walker or along its edge has
  /// changed its patch, however slowly. ≤ -1 disables it (default; docs/vio.md, session 27).
  double min_patch_ncc_first = -1.0;
  /// Fit the camera's motion on the trusted tracks (DynamicFilterOptions::min_trusted_matches):
  /// those with at least trusted_min_tests epipolar tests, the last of them static.
  bool trusted_model = true;
  int trusted_min_tests = 1;
  /// Trust contest: a test's model fitted on the trusted tracks gives way to the model fitted on
  /// the tracks it flags when that one passes more than this many times as many of the test's
  /// matches (0: off). A trusted set captured by one rigid mover (tracks born on a walker that
  /// covered the camera) flags the static scene, which then agrees on a model of its own.
  double trust_contest_ratio = 1.5;
  /// The contest runs while the trust is young: within this many frames of the last test whose
  /// model had too few trusted tracks and was fitted on all (a cold start); < 0: always.
  int trust_contest_frames = 40;
  /// Within trust_contest_frames of a cold start, a frame's flags claim movers only if its static
  /// features number at least trust_contest_ratio × its flags; otherwise they are isolated.
  bool young_trust_majority = true;
  /// A track claimed as a mover in each of its last this many frames keeps its flag through one test
  /// under the threshold (FrontendFeature::graced); 0: off.
  int mover_grace_claims = 3;
  /// Before a test's dynamic flag counts, the feature is re-searched along its epipolar line in
  /// the frame pair of that test (feature_epipolar_search.h); re-found: static, and the track moves
  /// to the re-found pixel.
  EpipolarSearchOptions epipolar_search;
  /// Before a test's dynamic flag counts, the feature's patch over that test's baseline is aligned
  /// by an affine warp (feature_affine_realign.h); the track moves to the aligned pixel.
  AffineRealignOptions affine_realign;
  /// After the tests and the consistency rule, a dynamic flag with fewer than groups.min_support
  /// other flags within groups.radius_factor × tracker.min_distance_px is isolated
  /// (FrontendFeature::isolated, dynamic_groups.h); min_support = 0 disables it.
  DynamicGroupOptions groups;
};

struct FrontendFeature {
  std::int64_t id = -1;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< raw (distorted) pixel in the current frame
  FeatureMotion motion = FeatureMotion::kUnknown;
  int baseline = 0;  ///< frames between the two views it was classified on (0: not classified)
  Eigen::Vector2d uv_then = Eigen::Vector2d::Zero();  ///< its pixel `baseline` frames ago (baseline > 0)
  double distance_px = 0.0;  ///< epipolar distance (or static-camera flow residual) of this frame's test; NaN if none
  /// The frame-to-frame test's distance (baseline 1) of every tracked feature, also of those
  /// classified on the long baseline; NaN if it did not run.
  double distance_1_px = std::numeric_limits<double>::quiet_NaN();
  /// motion == kDynamic with no other flag within the group radius (ImageFrontendOptions::groups): an
  /// unreliable track, not a moving object; left out of the estimator like a dynamic one.
  bool isolated = false;
  /// Flagged by mover_grace_claims: this frame's test was under the threshold, but the track was claimed
  /// as a mover in each of its last mover_grace_claims frames (motion is kDynamic).
  bool graced = false;
  int hits = 0;      ///< tests over the threshold among the track's last consistency_checks
  int checks = 0;    ///< tests kept (≤ consistency_checks)
};

struct FrontendFrameResult {
  std::vector<FrontendFeature> features;
  TrackingResult tracking;  ///< counts of the tracker (its features are the same as above)
  double static_ratio = 1.0;
  int n_static = 0, n_dynamic = 0, n_unknown = 0;  ///< n_dynamic: the flags in groups (not isolated)
  int n_rejected_appearance = 0;  ///< tracks rejected by the appearance check over the baseline
  int n_rejected_first_patch = 0;  ///< tracks rejected by the appearance check against their first frame
  int n_refound_epipolar = 0;     ///< dynamic flags withdrawn by the epipolar re-search
  int n_realigned_affine = 0;     ///< dynamic-flagged features moved by the affine re-alignment
  int n_unflagged_affine = 0;     ///< of those, the ones that turned static
  int n_refits_affine = 0;        ///< tests whose model was fitted again after the re-alignment
  int n_isolated = 0;             ///< dynamic flags without a flagged neighbour (groups): not counted as dynamic
  int n_contests_lost = 0;        ///< tests whose trusted model gave way to the model of the tracks it flagged
  int n_graced = 0;               ///< flags kept through a test under the threshold (mover_grace_claims)
  /// Young trust without a majority (young_trust_majority): this frame's flags are all isolated.
  bool trust_undecided = false;
  /// Status of the longest baseline run this frame (kTooFewMatches when none could run).
  ClassificationStatus status = ClassificationStatus::kTooFewMatches;
  MotionModel motion_model = MotionModel::kEstimated;  ///< of the longest baseline run this frame
  double tracking_ms = 0.0, classification_ms = 0.0;  ///< wall clock
};

class ImageFrontend {
 public:
  /// camera: the images' model (undistortion); mask: empty or the frames' size, non-zero where
  /// corners may be detected. Throws std::invalid_argument on bad options (baseline_frames < 1).
  ImageFrontend(ImageFrontendOptions options, std::shared_ptr<const CameraModel> camera, GrayImage mask = {});
  /// Tracks and classifies the next frame. Throws std::invalid_argument on an empty frame or one
  /// whose size differs from the previous one (FeatureTracker).
  /// R_cur_prev (optional): the camera's rotation from the previous frame to this one (x_cur = R x_prev + t),
  /// used by the tests when options().filter.known_rotation is set and by the tracker's gyro seed
  /// (options().tracker.gyro_klt).
  FrontendFrameResult process(const GrayImage& frame, const Eigen::Matrix3d* R_cur_prev = nullptr);
  const ImageFrontendOptions& options() const { return options_; }

 private:
  ImageFrontendOptions options_;
  FeatureTracker tracker_;
  DynamicFeatureFilter filter_;       ///< baseline 1
  DynamicFeatureFilter filter_long_;  ///< baseline k (threshold · k^e)
  /// history_[j]: positions of the features tracked in frame t − 1 − j (j < k).
  std::deque<std::unordered_map<std::int64_t, Eigen::Vector2d>> history_;
  /// rotations_[j]: R from frame t − 2 − j to frame t − 1 − j (R_cur_prev of frame t − 1 − j), if given.
  std::deque<std::optional<Eigen::Matrix3d>> rotations_;
  std::deque<GrayImage> frames_;  ///< frames_[j]: frame t − 1 − j (only with the appearance check, re-search or re-alignment)
  bool keep_frames() const {
    return options_.min_patch_ncc_baseline > -1.0 || options_.epipolar_search.enabled || options_.affine_realign.enabled;
  }
  std::unordered_set<std::int64_t> flagged_dynamic_;
  int frames_since_cold_start_ = 0;  ///< frames since a test's model was fitted on all its matches
  /// The trust is young at `age` frames after a cold start (the contest's and the claim rule's window).
  bool young_trust(int age) const { return options_.trust_contest_frames < 0 || age <= options_.trust_contest_frames; }
  /// Per live track: bit i = the test i frames ago exceeded the threshold; and the number of tests.
  struct TestHistory {
    std::uint16_t over = 0;
    int count = 0;
    bool dynamic = false;  ///< the rule's last decision
    int claim_run = 0;     ///< frames in a row up to the last one claimed as a mover (flagged, not isolated, not graced)
  };
  std::unordered_map<std::int64_t, TestHistory> tests_;
  /// min_patch_ncc_first: each live track's patch at its detection (a crop, `centre` = its pixel in it).
  struct FirstPatch {
    GrayImage crop;
    Eigen::Vector2d centre;
  };
  std::unordered_map<std::int64_t, FirstPatch> first_patch_;
};

/// The consistency rule on one track's test history (bit i: test i ago over the threshold): of the
/// last min(count, checks) tests, dynamic iff at least `hits` were over it, or at least one when
/// the track was dynamic before (hysteresis); unknown when count = 0.
FeatureMotion consistent_motion(std::uint16_t over, int count, int checks, int hits, bool was_dynamic = false);

/// A detection mask for a fisheye image: non-zero inside the circle of radius (radius_px − margin_px)
/// about the principal point (cx, cy); radius 0 gives an empty mask (whole image usable).
GrayImage circular_mask(int width, int height, double cx, double cy, double radius_px, double margin_px = 8.0);

}  // namespace slamkit
