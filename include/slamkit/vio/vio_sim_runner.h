// Runs the sliding-window estimator on a simulated visual-inertial run (sim/visual_inertial_sim.h):
// the IMU and the camera observations in time order, the estimate and the truth of every frame
// as trajectories, and the timings.
// Start-up (no ground truth): from the first frame after which the IMU shows motion
// (accelerometer std over the last 1 s ≥ 0.25 m/s², VINS-Mono's excitation check; EuRoC's
// MAVs stand still at first), frames join the start-up window when their tracks moved
// ≥ frame_parallax_px since the last window frame (or max_frame_gap frames later); a full window (window_frames) goes through
// initialize_from_frames (visual SfM + visual-inertial alignment, vio/visual_inertial_initializer.h).
// On failure the oldest window frame is dropped and the next frame retried; a run that ends
// first throws InputError ("too short to initialize", with the last failure). On success the
// estimator starts at the newest window frame from the aligned state; the window frames' states
// are the first samples of the estimate. The first frame's true yaw and position fix the gauge
// of the aligned states (unobservable for VIO; ATE uses SE(3) alignment anyway); nothing else
// of the truth is read. use_ground_truth restores the old start (true state at the first
// moving frame) for comparisons.
// Every observation is flagged static/dynamic by the simulator's labels (SimLabelClassifier,
// vio/feature_classifier.h); the estimator uses the flags only with options.dvi.enabled
// (baseline: dynamic observations are used like static ones).
#pragma once

#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "slamkit/core/trajectory.h"
#include "slamkit/sim/visual_inertial_sim.h"
#include "slamkit/vio/sliding_window_estimator.h"
#include "slamkit/vio/visual_inertial_initializer.h"

namespace slamkit {

struct VioStartupOptions {
  int window_frames = 10;           ///< frames in the SfM window
  double frame_parallax_px = 10.0;  ///< mean track motion since the last window frame to add one
  int max_frame_gap = 5;            ///< or after this many camera frames
  VisualSfmOptions sfm;             ///< focal_px and pixel_sigma are set from the run
  /// The alignment's options; its excitation check at 0.1 m/s² (VINS-Mono only warns below 0.25:
  /// the first seconds of the TUM-VI rooms are slow), scale and |g| are checked anyway.
  InitializerOptions alignment = [] {
    InitializerOptions a;
    a.min_accel_excitation = 0.1;
    return a;
  }();
  /// The estimator's prior on the initialized state (1σ; position stays the gauge's 1 mm).
  double prior_rotation_sigma = 0.02, prior_velocity_sigma = 0.1;
  bool use_ground_truth = false;    ///< start from the true state at the first moving frame
  /// With DVI on (SlidingWindowOptions::dvi.enabled), the start-up SfM leaves out the features the
  /// front end flagged dynamic (the baseline, like VINS-Mono, uses every feature).
  bool dvi_startup = true;
};

/// What the start-up did, with its errors against the truth (reported, never used).
struct VioStartupReport {
  std::string method;               ///< "visual-inertial initializer" or "ground truth"
  std::string message;              ///< the initializer's (or the last failure's) message
  int attempts = 0;                 ///< windows tried
  int window_frames = 0;
  double window_start_s = 0.0, window_end_s = 0.0;  ///< from the start of the run
  double scale_error = 0.0;         ///< |rms spread of the window positions, estimate / true − 1|
  double gravity_error_deg = 0.0;   ///< roll/pitch: angle between estimated and true up at the first window frame
  double velocity_error = 0.0;      ///< max ‖v − v_true‖ over the window (gauge-aligned) [m/s]
  double gyro_bias_error = 0.0;     ///< ‖b_g − b_g,true‖ at the newest window frame [rad/s]
  double rotation_rms_deg = 0.0;    ///< the accepted window's SfM rotations against the gyroscope
  double scale_rel_sigma = 0.0;     ///< the accepted window's scale σ / scale (alignment residual)
  int dynamic_left_out = 0;         ///< flagged observations the accepted window's SfM left out (DVI)
};

struct VioRunResult {
  Trajectory estimate, truth;  ///< one sample per frame (state columns: v, biases)
  std::vector<FrameEstimate> frames;
  double initialized_at_s = 0.0;  ///< when the estimator started (from the start of the run)
  VioStartupReport startup;
  double wall_time_s = 0.0;
  double cpu_time_s = 0.0;  ///< process CPU time of the run (the machine may be shared)
  double sequence_duration_s = 0.0;
  std::size_t keyframes = 0;
  double features_per_frame = 0.0;
};

/// progress(k, n, estimate) after every frame (may be empty). Throws InputError if the run has
/// no frames, no IMU before its first frame, or is too short to initialize.
VioRunResult run_vio_on_sim(const VisualInertialSim& sim, SlidingWindowOptions options,
                            const std::function<void(std::size_t, std::size_t, const FrameEstimate&)>& progress = {},
                            const VioStartupOptions& startup = {});

}  // namespace slamkit
