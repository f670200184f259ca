// Runs the sliding-window estimator on a simulated visual-inertial run (sim/visual_inertial_sim.h):
// the IMU and the camera observations in time order, the estimate and the truth of every frame
// as trajectories, and the timings. Start-up: the estimator starts at the first frame after
// which the IMU shows motion (accelerometer std over the last 1 s ≥ 0.25 m/s², VINS-Mono's
// excitation check; EuRoC's MAVs stand still at first), from the true state there (pose,
// velocity; biases set to zero); no ground truth is used afterwards.
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

namespace slamkit {

struct VioRunResult {
  Trajectory estimate, truth;  ///< one sample per frame (state columns: v, biases)
  std::vector<FrameEstimate> frames;
  double initialized_at_s = 0.0;  ///< time of the first state (from the start of the run)
  double wall_time_s = 0.0;
  double cpu_time_s = 0.0;  ///< process CPU time of the run (the machine may be shared)
  double sequence_duration_s = 0.0;
  std::size_t keyframes = 0;
  double features_per_frame = 0.0;
};

/// progress(k, n, estimate) after every frame (may be empty). Throws InputError if the run has
/// no frames or no IMU before its first frame.
VioRunResult run_vio_on_sim(const VisualInertialSim& sim, SlidingWindowOptions options,
                            const std::function<void(std::size_t, std::size_t, const FrameEstimate&)>& progress = {});

}  // namespace slamkit
