// SlidingWindowEstimator: a VINS-Mono-style optimization-based visual-inertial back end.
//
// Window: up to `window_size` keyframes, each one ImuState (R, p, v, b_g, b_a) variable
// x<id>; features as inverse depths l<n> anchored in the keyframe of their first observation
// (bearing from the camera model's unproject). Cost
//   ‖prior‖² + Σ_IMU ‖r_ij‖²_Σij + Σ_obs ρ_Cauchy(‖π(P) − z‖² / σ_px²)
// solved by the slamkit Optimizer (LM, inverse depths eliminated by the Schur complement).
// Frames: the IMU is preintegrated from the last keyframe; a frame becomes a keyframe when
// the mean pixel motion of the common tracks since the last keyframe reaches
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
#include <unordered_map>
#include <vector>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/imu_measurement.h"
#include "slamkit/core/parallel.h"
#include "slamkit/factors/imu_preintegration.h"
#include "slamkit/geometry/camera_models.h"

namespace slamkit {

struct FeatureObservation {
  std::uint64_t track_id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
};

struct CameraFrame {
  double stamp = 0.0;
  std::vector<FeatureObservation> features;
};

struct SlidingWindowOptions {
  int window_size = 10;                  ///< keyframes in the window
  double keyframe_parallax_px = 15.0;    ///< mean track motion that makes a keyframe
  int max_frames_between_keyframes = 4;  ///< a keyframe at least every this many frames
  double pixel_sigma = 1.0;              ///< [px]
  double cauchy_delta = 2.0;             ///< Cauchy scale on the whitened residual (σ units)
  double initial_depth = 3.0;            ///< [m] when a feature cannot be triangulated yet
  double min_depth = 0.1, max_depth = 50.0;
  double min_triangulation_angle_deg = 1.0;
  int max_iterations = 5;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  ImuNoise imu_noise;
  /// Prior on the first state (1σ): rotation [rad], position [m], velocity [m/s], biases.
  double prior_rotation_sigma = 1e-3, prior_position_sigma = 1e-3, prior_velocity_sigma = 0.05;
  double prior_gyro_bias_sigma = 5e-3, prior_accel_bias_sigma = 0.05;
  int num_threads = 1;
};

struct FrameEstimate {
  double stamp = 0.0;
  ImuState state;
  bool keyframe = false;
  int features = 0;            ///< observations of the frame
  int features_in_problem = 0; ///< features in the window's problem after this frame
  int iterations = 0;
  double solve_ms = 0.0, marginalization_ms = 0.0;
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
  const ImuState& latest_keyframe_state() const { return keyframes_.back().state; }
  const SlidingWindowOptions& options() const { return options_; }

 private:
  struct Keyframe {
    std::uint64_t id;
    double stamp;
    ImuState state;
    std::unordered_map<std::uint64_t, Eigen::Vector2d> pixels;  // by track id
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
  void add_keyframe(const CameraFrame& frame, const ImuState& predicted);
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
  std::deque<Keyframe> keyframes_;
  std::deque<ImuPreintegration> imu_factors_;  // [k]: keyframes_[k] → keyframes_[k + 1]
  std::unordered_map<std::uint64_t, Feature> features_;  // by track id
  std::shared_ptr<const Factor> prior_;
  std::vector<ImuMeasurement> imu_;
  ImuPreintegration pending_;  // last keyframe → last frame
  double last_stamp_ = 0.0;
  int frames_since_keyframe_ = 0;
  std::uint64_t next_keyframe_id_ = 0, next_feature_key_ = 0;
};

}  // namespace slamkit
