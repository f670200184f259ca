// Consistency evaluation of the landmark-SLAM filters on simulated runs (Bailey et al. 2006).
// Per run and per observation step k: pose error e_k = x̂_k − x_k (heading wrapped),
// NEES ε_k = e_kᵀ P_k⁻¹ e_k (χ²₃ when consistent), NIS of the update (χ² with 2·associated dof).
// Over N runs (seeds 1..N, the same noise draws for every filter): ANEES_k = (1/N) Σ ε_k with the
// two-sided (1 − α) bounds χ²_{N·3}(α/2)/N, χ²_{N·3}(1 − α/2)/N (N = 30: [2.188, 3.938]), the
// share of steps whose ANEES lies inside, RMSE over time and overall, and the final map NEES
// (mean over landmarks of e_mᵀ P_m⁻¹ e_m, 2 dof; known association only).
// The Monte-Carlo runner spreads the runs over a ThreadPool; each run is independent and
// writes only its own result, so the numbers do not depend on the number of threads.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/filters/landmark_filter.h"
#include "slamkit/sim/landmark_sim.h"

namespace slamkit {

struct FilterRunResult {
  std::uint64_t seed = 0;
  std::vector<double> time;                  // s, at every evaluated (observation) step
  std::vector<Eigen::Vector3d> truth, estimate;
  std::vector<Eigen::Matrix3d> covariance;
  std::vector<double> nees;                  // pose NEES per evaluated step
  std::vector<int> landmarks;                // map size per evaluated step
  double nis_sum = 0;                        // Σ NIS and Σ dof over the run
  long nis_dof = 0;
  std::vector<double> step_ms;               // wall time of predict (+ update) per control step
  std::vector<int> step_landmarks;           // map size at each control step
  std::vector<LandmarkEstimate> final_map;
  double map_nees = std::numeric_limits<double>::quiet_NaN();
  bool finite = true;                        // no NaN/Inf in any estimate or covariance
};

struct FilterRunOptions {
  bool evaluate = true;      // false: timing only (no covariance queries), for scaling runs
  bool final_map = true;     // query the final map (and its NEES)
  bool map_nees = true;      // needs ids = true landmark indices (known association)
};

using FilterMaker = std::function<std::unique_ptr<LandmarkFilter>()>;

/// Runs one filter over one simulated run; `landmarks` is the true map (for the map NEES).
FilterRunResult run_filter_on_simulation(LandmarkFilter* filter, const LandmarkSimRun& run,
                                         const LandmarkSimOptions& sim,
                                         const std::vector<Eigen::Vector2d>& landmarks,
                                         const FilterRunOptions& options = {});

struct MonteCarloOptions {
  int runs = 30;
  std::uint64_t first_seed = 1;  // runs use seeds first_seed .. first_seed + runs − 1
  int threads = 0;               // ≤ 0: all cores
  FilterRunOptions run;
  /// Called (serialized) after each finished run with (done, total).
  std::function<void(int, int)> progress;
};

/// Seeds 1..N: every filter given the same world, options and seeds sees the same noise draws.
std::vector<FilterRunResult> run_monte_carlo(const FilterMaker& make, const std::vector<Eigen::Vector2d>& landmarks,
                                             const std::vector<Eigen::Vector2d>& waypoints,
                                             const LandmarkSimOptions& sim, const MonteCarloOptions& options);

struct ConsistencySummary {
  int runs = 0;
  std::vector<double> time, anees, rmse_position, rmse_heading;  // over the evaluated steps
  double anees_mean = 0;                 // mean over time of ANEES_k
  double anees_lo = 0, anees_hi = 0;     // two-sided bounds
  double confidence = 0.95;
  double fraction_in_bounds = 0;         // share of steps with ANEES_k inside the bounds
  double rmse_position_total = 0;        // m, over all runs and steps
  double rmse_heading_total = 0;         // rad
  double anis = 0;                       // Σ NIS / Σ dof over all runs (1 when consistent)
  double map_nees = std::numeric_limits<double>::quiet_NaN();  // mean over runs
  double time_per_step_mean_ms = 0, time_per_step_max_ms = 0;
  int landmarks = 0;                     // final map size (mean over runs, rounded)
  bool finite = true;
};

/// Throws InputError when the runs differ in length (they must share the world and options).
ConsistencySummary summarize_consistency(const std::vector<FilterRunResult>& runs, double confidence = 0.95);

}  // namespace slamkit
