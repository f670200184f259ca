// Synthetic calibration problems with known truth ("sim:calib2d", "sim:calib3d").
//
// calib2d: a differential-drive robot drives `laps` laps of a figure of two squares (one
//   turned left, one right, with in-place turns at two corners) and the truth follows its
//   wheels: true wheel scales k_l, k_r and baseline b differ from the nominal (1, 1, b₀) by up to
//   `bias` (relative); the raw wheel readings v = v_true / k are what the odometry edges carry
//   (EDGE_SE2_ODOM_DIFFERENTIAL_CALIB, VERTEX_ODOM_DIFFERENTIAL at the nominal values), and
//   the true motion is U(K_true) ⊞ n_odo (wheel slip). A scanner mounted at an unknown offset S
//   (the file's VERTEX_SE2 holds the drawing's nominal offset) measures sensor-frame relative
//   poses (X_i S)⁻¹ (X_j S) ⊞ n_scan between consecutive poses and as loop closures between
//   laps (EDGE_SE2_CALIB). path=line drives straight only (the baseline and the offset
//   translation are then unobservable).
// calib3d: a 6-DoF platform (rolling and pitching while it circles, climbing and descending)
//   with plain odometry (EDGE_SE3:QUAT) and a sensor at an unknown PARAMS_SE3OFFSET measuring
//   sensor-frame relative poses (EDGE_SE3_OFFSET, the same parameter on both sides); the
//   generated graph estimates that parameter (calibration.estimate_offset_parameters); the
//   sensor relates consecutive poses, poses 12 steps apart and the same place one lap earlier.
// Noise: Z = Z_true ⊞ n, n ~ N(0, diag σ²), information Σ⁻¹ in the edge's error coordinates.
// Initial estimates: dead reckoning with the nominal calibration. Deterministic per seed.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

struct CalibrationSimOptions {
  std::string world = "calib2d";  ///< "calib2d" or "calib3d"
  std::string path = "figure";    ///< calib2d: "figure" or "line"
  /// calib2d: "differential" (wheel readings, VERTEX_ODOM_DIFFERENTIAL) or "linear" (the nominal
  /// dead-reckoning increments (Δx, Δy, Δθ) with a VERTEX_ODOM_LINEAR K to estimate; no truth for K)
  std::string odometry = "differential";
  int laps = 3;
  double step = 0.25;               ///< metres per pose (calib2d), per step (calib3d)
  double bias = 0.05;               ///< max relative error of the nominal wheel parameters
  double nominal_baseline = 0.5;    ///< metres
  double odometry_sigma_t = 0.005;  ///< slip per step, metres
  double odometry_sigma_r = 0.002;  ///< radians
  double scan_sigma_t = 0.01;       ///< metres
  double scan_sigma_r = 0.002;      ///< radians
  double loop_radius = 0.6;         ///< loop closures to poses of earlier laps this near
  std::uint32_t seed = 1;
};

/// The true value of each calibration parameter, named as CalibrationReport names them
/// ("offset[1000].x", "odometry[1001].baseline", "params_se3offset[0].rx", ...).
using CalibrationTruth = std::vector<std::pair<std::string, double>>;

/// Generates the problem; fills `truth` (optional) and `ground_truth` (optional: the same graph
/// with the true poses and calibration). Throws InputError on bad options.
PoseGraph generate_calibration_problem(const CalibrationSimOptions& options, CalibrationTruth* truth = nullptr,
                                       PoseGraph* ground_truth = nullptr);

/// "sim:calib2d", "sim:calib3d?seed=3&laps=2&path=line&odometry=linear": true if `spec` names a calibration
/// problem; fills `options`. Parameters: seed (0..2^32-1), laps (1..1000), bias ([0, 0.5)), and for
/// calib2d path (figure | line) and odometry (differential | linear); numbers must be whole decimal
/// texts. Anything else throws InputError naming the spec and the parameter.
bool parse_calibration_sim_spec(const std::string& spec, CalibrationSimOptions* options);

/// The spec that parse_calibration_sim_spec reads back to the same world, seed, laps, bias, path
/// and odometry.
std::string to_calibration_sim_spec(const CalibrationSimOptions& options);

}  // namespace slamkit
