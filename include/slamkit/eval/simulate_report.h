// Simulated visual-inertial runs in `slamkit report`: documents of kind "simulate"
// (`slamkit simulate --vi ... --json`) with at least source, seed, dynamic, duration_s, frames,
// features_per_frame {mean, min}, dynamic_share, static_ratio {mean, min} and spline_fit
// {position_rmse_m, rotation_rmse_deg}; optional output, camera {model}, landmarks {static,
// dynamic, groups}. One table: what each run holds, so a reader sees which scene the VIO and
// DVI results beside it were measured on.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace slamkit {

struct SimulateRunData {
  std::string source, label, dynamic, camera_model;
  long long seed = 0;
  int frames = 0, static_landmarks = 0, dynamic_landmarks = 0, groups = 0;
  double duration_s = 0, features_mean = 0, features_min = 0, dynamic_share = 0;
  double static_ratio_mean = 0, static_ratio_min = 0, fit_position_rmse_m = 0, fit_rotation_rmse_deg = 0;
};

/// Validates and reads a simulate document; throws InputError(source, 0, field, message).
SimulateRunData simulate_run_from_json(const nlohmann::json& j, const std::string& source);
/// The HTML section (id "simulations") with one row per run.
std::string simulate_report_section(const std::vector<SimulateRunData>& runs);

}  // namespace slamkit
