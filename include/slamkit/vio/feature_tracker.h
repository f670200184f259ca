// Feature tracking of the DVI front end (P4 algorithm 1, first half; docs/frontend.md):
//   detect   goodFeaturesToTrack (Shi-Tomasi min-eigenvalue corners) in the free part of the
//            image: the user mask (non-zero = usable) minus a disk of radius min_distance around
//            every feature already tracked, so new corners spread; optionally per grid cell
//   refine   cornerSubPix on the new corners
//   track    pyramidal Lucas-Kanade (calcOpticalFlowPyrLK) from the previous frame, then back
//            again: a track survives if |p_prev − KLT⁻¹(KLT(p_prev))| ≤ forward_backward_px and
//            its new position lies at least border_px inside the image; under large motion
//            (median flow > median_flow_retry_px) KLT runs a second time from the median flow and
//            each feature keeps the candidate with the lower photometric residual
//   gyro seed   given the camera's rotation R_cur_prev (gyroscope) and the camera model, each
//            feature's KLT starts at its infinite-depth prediction p' = π(R π⁻¹(p)) (the homography
//            K R K⁻¹ through the distortion) instead of at p (VINS-Fusion, OpenVINS): the flow left
//            to KLT is the translation's parallax only. kSeed replaces the zero-flow start (the median
//            retry then runs on the flow relative to the prediction); kCandidate keeps the zero-flow
//            and median-flow candidates and adds the predicted one (lowest residual wins, ambiguity
//            rule as for the retry). No camera, no rotation or one that is not a finite rotation:
//            the unseeded tracker, reported (TrackingResult::gyro_seeded = false)
//   robust refine  optionally (rlof_refine) each KLT result is refined by robust local optical flow
//            (OpenCV contrib's RLOF: a support region cut by cross-based segmentation of the patch
//            and a shrinked-Hampel M-estimator, Senst et al. 2012-2016), started at KLT's flow; where
//            the patch straddles a depth or motion edge, the pixels of the other surface are cut out
//            or down-weighted instead of dragging the least-squares fit (docs/frontend.md)
//   appearance  a track whose patch about its new position does not look like the patch about
//            its old one (zero-mean NCC < min_patch_ncc) is lost: the corner is no surface point
//            (an occlusion edge or a T-junction of surfaces at different depths, whose background
//            slides behind the foreground edge) or KLT slipped (docs/frontend.md)
//   refill   each frame, new corners are detected until max_features are tracked.
// Every feature keeps its id (increasing from 0, never reused) while it is tracked.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/vio/gray_image.h"

namespace slamkit {

class CameraModel;

/// What the RLOF refinement (see the header comment) changes: nothing (kOff), the tracks
/// themselves (kTrack: every consumer sees the refined positions), or only the positions the
/// epipolar test reads (kTest: a second chain, TrackedFeature::uv_test, refined frame to frame from
/// its own previous position; the tracks, and so the estimator, keep KLT's positions).
enum class RlofRefine { kOff, kTrack, kTest };
const char* rlof_refine_name(RlofRefine mode);  ///< "off", "track", "test"
/// "off", "track" (alias "on"), "test"; std::invalid_argument otherwise.
RlofRefine parse_rlof_refine(const std::string& name);

/// How the gyroscope's rotation seeds KLT (see the header comment).
enum class GyroKlt { kOff, kSeed, kCandidate };
const char* gyro_klt_name(GyroKlt mode);  ///< "off", "seed", "candidate"
/// "off", "seed" (alias "on"), "candidate"; std::invalid_argument otherwise.
GyroKlt parse_gyro_klt(const std::string& name);

struct FeatureTrackerOptions {
  int max_features = 150;         ///< features kept per frame (VINS-Mono's default)
  double min_distance_px = 30.0;  ///< minimum distance between features
  double quality_level = 0.01;    ///< Shi-Tomasi: corners weaker than this × the strongest are dropped
  int block_size = 3;             ///< Shi-Tomasi covariance window
  int grid_cols = 0, grid_rows = 0;  ///< > 0: detect per cell, max_features / cells each (spreads corners)
  int subpix_half_window = 5;     ///< cornerSubPix window (2h+1)²; 0 disables the refinement
  int klt_window = 21;            ///< KLT window side (px)
  int klt_pyramid_levels = 3;     ///< KLT pyramid levels above the full image
  int klt_max_iterations = 30;
  double klt_epsilon = 0.01;
  double forward_backward_px = 1.0;  ///< forward-backward check; ≤ 0 disables it
  /// If the median KLT flow exceeds this, track again from the median flow and keep the result
  /// with the lower patch residual (repeated textures under large motion); ≤ 0 disables it.
  double median_flow_retry_px = 8.0;
  /// With the retry: if the two KLT candidates (from zero flow and from the median flow) both
  /// converge, lie more than this apart and their residuals are within ambiguity_ratio of each
  /// other, the match is ambiguous (two motifs of a repeated texture fit) and the track is lost
  /// (counted in lost_klt); ≤ 0 disables it.
  double ambiguity_px = 2.0;
  double ambiguity_ratio = 0.3;  ///< min(residual) / max(residual) above this ⇒ ambiguous (2 px / 0.3 since session 23)
  /// > 0: a track whose KLT photometric residual exceeds this × the frame's median residual is
  /// lost (counted in lost_klt). Off by default: it removes KLT mismatches on rigid scenes but
  /// also the tracks on deforming movers (docs/frontend.md).
  double max_residual_ratio = 0.0;
  double border_px = 1.0;         ///< tracks closer than this to the image border are dropped
  /// Appearance check between the previous and the current frame: a track whose zero-mean NCC
  /// (patch_ncc, half size patch_half_px) is below this is lost (lost_appearance); ≤ -1 disables it.
  double min_patch_ncc = -1.0;
  int patch_half_px = 7;          ///< NCC patch (2h+1)²
  /// KLT seeded by the gyroscope's rotation (needs a camera model and a rotation per frame).
  GyroKlt gyro_klt = GyroKlt::kOff;
  /// Refine by robust local optical flow (RLOF, cross-based support region, M-estimator), started
  /// at KLT's flow: off, the tracks, or only the test positions (docs/frontend.md, sessions 33–34:
  /// kTrack halves the static false alarms on the rendered rooms; the default since session 34).
  RlofRefine rlof_refine = RlofRefine::kTrack;
  /// A refinement that moves the position this far or farther from where KLT's flow puts it is not
  /// taken (kTrack: KLT's position is kept; kTest: the test chain restarts at KLT's position).
  double rlof_max_shift_px = 3.0;
};

/// The infinite-depth prediction of raw pixel uv after the camera rotates by R_cur_prev
/// (x_cur = R x_prev): π(R π⁻¹(uv)). False (out untouched) if uv does not unproject or R·bearing
/// does not project.
bool predict_by_rotation(const CameraModel& camera, const Eigen::Matrix3d& R_cur_prev, const Eigen::Vector2d& uv,
                         Eigen::Vector2d* out);

/// Zero-mean normalized cross-correlation of the (2·half+1)² patches about pa in a and pb in b
/// (bilinear samples, gain and bias invariant), in [-1, 1]; NaN if a patch leaves its image;
/// 1 if both patches are flat (no texture: nothing to disagree on).
double patch_ncc(const GrayImage& a, const Eigen::Vector2d& pa, const GrayImage& b, const Eigen::Vector2d& pb, int half);

struct TrackedFeature {
  std::int64_t id = -1;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();       ///< position in the current frame (px)
  Eigen::Vector2d prev_uv = Eigen::Vector2d::Zero();  ///< position in the previous frame (age > 0)
  /// Position for the epipolar test: uv, except with rlof_refine = kTest (its own RLOF chain).
  Eigen::Vector2d uv_test = Eigen::Vector2d::Zero();
  int age = 0;  ///< frames this feature has been tracked; 0: detected in this frame
};

struct TrackingResult {
  std::vector<TrackedFeature> features;  ///< tracked ones (age > 0) first, then new detections
  int tracked = 0;           ///< features carried over from the previous frame
  int lost_klt = 0;          ///< KLT status 0 (not found)
  int lost_forward_backward = 0;
  int lost_border = 0;
  int lost_appearance = 0;   ///< patch NCC with the previous frame below min_patch_ncc
  int detected = 0;          ///< new corners this frame
  bool gyro_seeded = false;  ///< KLT was seeded by the rotation this frame (gyro_klt on, rotation usable)
  int predicted = 0;         ///< features whose seed is the rotation's prediction (the others: zero flow)
  int rlof_refined = 0;      ///< tracks (kTrack) or test positions (kTest) the RLOF refinement moved
  /// The previous/current pixel pairs of the tracked features, the input of DynamicFeatureFilter.
  void matches(std::vector<Eigen::Vector2d>* prev, std::vector<Eigen::Vector2d>* cur,
               std::vector<std::int64_t>* ids = nullptr) const;
};

class FeatureTracker {
 public:
  /// mask: empty (whole image usable) or the size of every frame, non-zero where corners may be
  /// detected. Throws std::invalid_argument on bad options.
  /// camera: the images' model, needed by gyro_klt (without it the tracker is unseeded).
  explicit FeatureTracker(FeatureTrackerOptions options = {}, GrayImage mask = {},
                          std::shared_ptr<const CameraModel> camera = nullptr);
  ~FeatureTracker();
  FeatureTracker(FeatureTracker&&) noexcept;
  FeatureTracker& operator=(FeatureTracker&&) noexcept;

  /// Tracks the features into `frame` and refills them. Throws std::invalid_argument if the frame
  /// is empty, its size differs from the previous frame's, or the mask's size differs from it.
  /// R_cur_prev (optional): the camera's rotation from the previous frame to this one, used by
  /// gyro_klt; null or not a finite rotation: unseeded.
  TrackingResult track(const GrayImage& frame, const Eigen::Matrix3d* R_cur_prev = nullptr);
  /// Stops tracking the given ids (e.g. features classified dynamic); their neighbourhoods free up.
  void drop(const std::vector<std::int64_t>& ids);
  /// Moves tracked features to corrected positions in the current frame (e.g. re-found on their
  /// epipolar line); ids not tracked are ignored. The next frame tracks them from there.
  void relocate(const std::vector<std::int64_t>& ids, const std::vector<Eigen::Vector2d>& uv);
  const FeatureTrackerOptions& options() const { return options_; }

 private:
  struct State;
  FeatureTrackerOptions options_;
  std::shared_ptr<const CameraModel> camera_;
  std::unique_ptr<State> state_;
};

}  // namespace slamkit
