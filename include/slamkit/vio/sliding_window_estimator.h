// SlidingWindowEstimator: a VINS-Mono-style optimization-based visual-inertial back end.
//
// Window: up to `window_size` keyframes, each one ImuState (R, p, v, b_g, b_a) variable
// x<id>; features as inverse depths l<n> anchored in the keyframe of their first observation
// (bearing from the camera model's unproject). Cost
//   ‖prior‖² + Σ_IMU ‖r_ij‖²_Σij + Σ_obs ρ_Cauchy(‖π(P) − z‖² / σ_px²)
// solved by vio/dense_window_solver.h (a dense window system, inverse depths eliminated on the
// fly, LM; `dense_solver = false` goes through the generic slamkit Optimizer instead, the
// reference the dense path is tested against).
// DVI (issue 13, `dvi`): each observation carries the front end's static/dynamic flag; with
// dvi on, dynamic observations are not used, a frame's visual factors are weighted by α(M),
// M = static / all of the frame, and a frame with M < θ keeps no visual factors (IMU only).
// dvi off (default) is the baseline: every feature is used as static, α = 1 (VINS-Mono).
// Frames: the IMU is preintegrated from the last keyframe; a frame becomes a keyframe when
// the mean pixel motion of the common tracks since the last keyframe, less the motion the
// IMU-predicted rotation explains (rotation_compensated_parallax), reaches
// keyframe_parallax_px, or after max_frames_between_keyframes frames. A non-keyframe (the
// newest frame when it adds little parallax) is dropped with its visual measurements and its
// IMU kept (integration continues to the next keyframe), as VINS-Mono's "marginalize the
// second newest" does, at no cost; its state is the IMU prediction from the last keyframe.
// When the window is full the oldest keyframe and the features anchored in it are
// marginalized (vio/marginalization.h, two Schur passes) into a MarginalizationPrior with
// first-estimate Jacobians; features seen again later move their anchor to their next
// keyframe (VINS-Mono's depth shift: their later observations then count in the prior and
// in the window, the approximation VINS-Mono makes to keep long tracks). Features are triangulated (two-view midpoint with the current
// estimates) before they enter the problem; a feature whose inverse depth leaves
// [1/max_depth, 1/min_depth] is dropped.
// Start-up: initialize() with the first state (from the visual-inertial initializer or
// given) anchors the gauge by a prior on it. Not thread-safe.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/imu_measurement.h"
#include "slamkit/core/parallel.h"
#include "slamkit/factors/imu_preintegration.h"
#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/dense_window_solver.h"

namespace slamkit {

struct FeatureObservation {
  std::uint64_t track_id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  bool dynamic = false;  ///< the front end's classification (vio/feature_classifier.h)
  bool classified = true;  ///< false: not tested yet (a new track); counted static, see DviOptions
};

struct CameraFrame {
  double stamp = 0.0;
  std::vector<FeatureObservation> features;
  int dynamic_groups = -1;  ///< moving groups the front end sees (−1: unknown); for the adaptive θ
};

/// Adaptive visual weighting (DVI-SLAM, issue 13 part 2). α(M) for M = static / all features of
/// a frame (with `ratio_of_classified`: static / classified, the front end's untested new tracks left
/// out of both counts; 1 when none is classified): kOne α = 1, kRatio α = M, kPower α = M^alpha_power. θ: fixed, or (adaptive_theta)
/// θ = min(theta_max, theta + theta_per_group · dynamic_groups) when the front end counts groups.
struct DviOptions {
  enum class Alpha { kOne, kRatio, kPower };
  bool enabled = false;  ///< off: baseline, dynamic flags ignored, α = 1
  Alpha alpha = Alpha::kPower;  // α = M², measured best of 1, M, M², M³ on rendered rooms (docs/frontend.md)
  double alpha_power = 2.0;
  double theta = 0.5;
  bool ratio_of_classified = false;
  bool adaptive_theta = false;
  double theta_per_group = 0.05, theta_max = 0.8;
  /// θ for a frame that sees `groups` moving groups (−1: unknown ⇒ the fixed θ).
  double theta_for(int groups) const;
  double alpha_of(double static_ratio) const;
};
/// "1" | "M" | "M^k" (k > 0); InputError (field "alpha") otherwise.
void parse_dvi_alpha(const std::string& text, DviOptions* o);
/// A number in [0, 1], or "adaptive" / "adaptive:BASE,PER_GROUP,MAX"; InputError (field "theta") otherwise.
void parse_dvi_theta(const std::string& text, DviOptions* o);

struct SlidingWindowOptions {
  int window_size = 10;                  ///< keyframes in the window
  double keyframe_parallax_px = 15.0;    ///< mean track motion that makes a keyframe
  int max_frames_between_keyframes = 6;  ///< a keyframe at least every this many frames
  /// Parallax of the keyframe test without the IMU-predicted rotation (see add_frame): measured
  /// on the full rooms (docs/vio.md), raw parallax made 60 % of the frames keyframes, a window
  /// of ≈ 0.8 s with little baseline, and drift (room2 0.085 m → 0.020 m, seed 1).
  bool rotation_compensated_parallax = true;
  double pixel_sigma = 1.0;              ///< [px]
  double cauchy_delta = 2.0;             ///< Cauchy scale on the whitened residual (σ units)
  double initial_depth = 3.0;            ///< [m] when a feature cannot be triangulated yet
  double min_depth = 0.1, max_depth = 50.0;
  double min_triangulation_angle_deg = 1.0;
  int max_iterations = 5;
  bool dense_solver = true;  ///< vio/dense_window_solver.h; false: the generic Optimizer (no DVI weights)
  DviOptions dvi;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  ImuNoise imu_noise;
  /// Prior on the first state (1σ): rotation [rad], position [m], velocity [m/s], biases.
  double prior_rotation_sigma = 1e-3, prior_position_sigma = 1e-3, prior_velocity_sigma = 0.05;
  double prior_gyro_bias_sigma = 5e-3, prior_accel_bias_sigma = 0.05;
  int num_threads = 1;
  /// Post-solve outlier rejection (VINS-Fusion's outliersRejection, 3 px at f = 460 there): after a
  /// solve, a feature whose mean reprojection error over its non-anchor observations exceeds this
  /// [px] is removed from the window; its track re-enters as a new feature at its next keyframe
  /// (as in VINS-Fusion). Applies in both modes. 0: off (default: measured worse on the rendered
  /// high-dynamic rooms, docs/vio.md, session 27).
  double outlier_reprojection_px = 0.0;
};

struct FrameEstimate {
  double stamp = 0.0;
  ImuState state;
  bool keyframe = false;
  int features = 0;            ///< observations of the frame
  int features_in_problem = 0; ///< features in the window's problem after this frame
  int iterations = 0;
  double solve_ms = 0.0, marginalization_ms = 0.0;
  double static_ratio = 1.0;   ///< M of the frame (front-end flags; DviOptions::ratio_of_classified)
  double visual_weight = 1.0;  ///< α(M) its visual factors got (0: dropped)
  bool visual_dropped = false; ///< DVI: M < θ, the frame kept no visual factors
  int outliers_rejected = 0;   ///< features removed after this frame's solve (outlier_reprojection_px)
};

class SlidingWindowEstimator {
 public:
  SlidingWindowEstimator(SlidingWindowOptions options, std::shared_ptr<const CameraModel> camera,
                         const SE3& T_imu_cam);

  /// Starts the window at `stamp` with `state` (its prior anchors the gauge).
  void initialize(double stamp, const ImuState& state);
  bool initialized() const { return !keyframes_.empty(); }
  /// IMU samples, stamps increasing (InputError naming the field "imu stamp" otherwise).
  void add_imu(const ImuMeasurement& m);
  /// Processes a frame (after the IMU up to its stamp). InputError if the frame goes back in
  /// time or the IMU does not reach it; std::logic_error before initialize().
  FrameEstimate add_frame(const CameraFrame& frame);

  std::size_t num_keyframes() const { return keyframes_.size(); }
  std::size_t num_features() const { return features_.size(); }
  int outliers_rejected() const { return outliers_rejected_; }  ///< features removed by reject_outliers so far
  const ImuState& latest_keyframe_state() const { return keyframes_.back().state; }
  const SlidingWindowOptions& options() const { return options_; }

 private:
  struct Keyframe {
    std::uint64_t id;
    double stamp;
    ImuState state;
    std::unordered_map<std::uint64_t, Eigen::Vector2d> pixels;  // by track id
    double visual_weight = 1.0;  // α of its observations
  };
  struct Feature {
    std::uint64_t key_index;   // l<key_index>
    std::uint64_t anchor;      // keyframe id
    Eigen::Vector3d bearing;   // anchor camera frame, unit
    double inv_depth;
    bool triangulated = false;
    std::vector<std::pair<std::uint64_t, Eigen::Vector2d>> obs;  // (keyframe id, pixel), not the anchor's
  };

  const Keyframe* keyframe(std::uint64_t id) const;
  bool try_triangulate(Feature& f) const;
  /// Mean reprojection error [px] of f's non-anchor observations at the current estimates (NaN: none).
  double mean_reprojection_error_px(const Feature& f) const;
  /// outlier_reprojection_px: removes the features over it, returns how many.
  int reject_outliers();
  /// visual_weight 0: the keyframe keeps its pixels (parallax) but no observation.
  void add_keyframe(const CameraFrame& frame, const ImuState& predicted, double visual_weight);
  /// The window as a dense problem: states, features (only_oldest: anchored in the oldest), their
  /// track ids, the prior and IMU factors (only_oldest: those touching the oldest).
  void dense_problem(bool only_oldest, std::vector<ImuState>& states, std::vector<WindowFeature>& features,
                     std::vector<std::uint64_t>& tracks, std::vector<WindowStateFactor>& factors) const;
  int solve_dense();
  void marginalize_oldest_dense();
  /// Factors of the window (all, or only those that touch the oldest keyframe).
  void build(FactorGraph& graph, Values& values, bool only_oldest, std::vector<Key>* oldest_features) const;
  int solve();
  void marginalize_oldest();

  SlidingWindowOptions options_;
  std::shared_ptr<const CameraModel> camera_;
  SE3 T_imu_cam_;
  ThreadPool pool_;
  std::shared_ptr<const NoiseModel> pixel_noise_;
  std::shared_ptr<const RobustKernel> kernel_;
  DenseWindowSolver dense_;
  std::deque<Keyframe> keyframes_;
  std::deque<ImuPreintegration> imu_factors_;  // [k]: keyframes_[k] → keyframes_[k + 1]
  std::unordered_map<std::uint64_t, Feature> features_;  // by track id
  std::shared_ptr<const Factor> prior_;
  std::vector<ImuMeasurement> imu_;
  ImuPreintegration pending_;  // last keyframe → last frame
  double last_stamp_ = 0.0;
  int frames_since_keyframe_ = 0;
  std::uint64_t next_keyframe_id_ = 0, next_feature_key_ = 0;
  int outliers_rejected_ = 0;
};

}  // namespace slamkit
