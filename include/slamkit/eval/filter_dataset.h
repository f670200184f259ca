// Landmark-SLAM filters on the real datasets (io/landmark_dataset.h): one replay loop shared by
// `slamkit filter --dataset` and bench/fastslam_real. The event stream (controls and scans in
// time order) goes through a filter, each step is timed (thread CPU time), dead reckoning with
// the same motion model runs beside it, and the run is scored at every scan:
//   MRCLAM: pose error against the Vicon pose interpolated at the scan time (heading wrapped),
//     RMSE of position and heading, pose NEES e_kᵀ P_k⁻¹ e_k (scans with a regular P only),
//     final map error against the surveyed landmarks (known ids);
//   Victoria Park: no ground truth; RMS distance to the GPS fixes (nearest scan within 0.25 s)
//     after the least-squares 2-D rotation + translation of the estimate onto them, next to the
//     same figure for dead reckoning (a qualitative check).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/eval/filter_consistency.h"
#include "slamkit/eval/svg.h"
#include "slamkit/filters/landmark_filter.h"
#include "slamkit/io/landmark_dataset.h"

namespace slamkit {

/// "mrclam:DIR:ROBOT" (robot 1..5) or "victoria:DIR"; InputError naming the field otherwise
/// (and the readers' file:line errors for malformed files).
LandmarkDataset load_landmark_dataset(const std::string& spec);

/// Unicycle odometry noise used on MRCLAM: constant plus proportional parts (chosen, not fitted).
struct UnicycleNoise {
  double sigma_v = 0.05, sigma_w = 0.1, sigma_v_per_v = 0.2, sigma_w_per_w = 0.2;
};

/// The motion and sensor models a filter runs with on a dataset.
struct DatasetModels {
  std::shared_ptr<const MotionModel> motion;
  RangeBearingModel sensor{1, 1};
  std::string description;  // one line for logs and JSON
};

/// MRCLAM: UnicycleModel(noise) and the sensor σ estimated from the data (robust σ =
/// 1.4826 · median |z − h(x_vicon, m_surveyed)|, times sensor_scale). Victoria Park: the car
/// model with σ_v 2 m/s, σ_α 6°, sensor σ_r 1 m, σ_b 3° (the commonly used setup).
DatasetModels dataset_models(const LandmarkDataset& ds, const UnicycleNoise& noise = {}, double sensor_scale = 1.0);

/// Ground-truth pose at time t (linear, the angle through its wrapped difference); requires truth.
Eigen::Vector3d dataset_truth_at(const LandmarkDataset& ds, double t);
/// Robust σ of (range, bearing) residuals at the truth poses and the surveyed landmarks.
Eigen::Vector2d dataset_measurement_sigmas(const LandmarkDataset& ds);
/// RMS distance after the least-squares 2-D rotation + translation of `est` onto `ref`.
double aligned_rms(const std::vector<Eigen::Vector2d>& est, const std::vector<Eigen::Vector2d>& ref);

struct DatasetRunOptions {
  int progress_every = 1000;  // scans between progress calls (≤ 0: none)
  /// Called with (scans done, total scans, landmarks in the map, mean ms/step so far).
  std::function<void(int, int, int, double)> progress;
};

struct DatasetRunResult {
  std::string dataset;
  int events = 0, scans = 0;
  /// Per scan: time, estimate, covariance, NEES (NaN without truth or a singular P), map size;
  /// truth is filled only when the dataset has it. Per event: step_ms. Final map.
  FilterRunResult run;
  std::vector<Eigen::Vector3d> dead_reckoning;  // per scan
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double rmse_position = kNaN, rmse_heading = kNaN, dead_reckoning_rmse_position = kNaN;  // m, rad
  double mean_nees = kNaN;  // over the scans with a regular covariance
  int nees_scans = 0;
  double map_rmse = kNaN;   // m, over the mapped surveyed landmarks
  int mapped_true_landmarks = 0;
  int landmarks = 0;       // final map size
  double time_per_step_mean_ms = 0, time_per_step_max_ms = 0, time_per_scan_ms = 0;
  double gps_rms = kNaN, dead_reckoning_gps_rms = kNaN;  // Victoria Park
  int gps_matched = 0;
};

/// Replays every event of `ds` through `filter` (predict on controls, update on scans) and
/// dead-reckons with `dead_reckoning` beside it. The filter must start at ds.initial_pose.
DatasetRunResult run_filter_on_dataset(LandmarkFilter* filter, const MotionModel& dead_reckoning,
                                       const LandmarkDataset& ds, const DatasetRunOptions& options = {});

/// Map (estimate, dead reckoning, ground truth or aligned GPS, landmarks with 3σ ellipses) and,
/// with ground truth, the pose error with ±3σ over time.
SvgWriter plot_dataset_run(const std::string& label, const DatasetRunResult& result, const LandmarkDataset& ds);

}  // namespace slamkit
