// Filter runs in `slamkit report`: documents of kind "filter" (`slamkit filter --json`) with
// at least rmse_position, rmse_heading [deg], anees, anees_bounds [lo, hi], fraction_in_bounds,
// time_per_step_ms {mean, max}, landmarks, runs; optional label, algorithm, world, association,
// active, anis, map_nees and series {time, anees, rmse_position}. Shown side by side: one table
// and ANEES / RMSE curves per world.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace slamkit {

struct FilterRunData {
  std::string source, label, algorithm, world, association;
  int runs = 0, landmarks = 0, active = 0;
  double rmse_position = 0, rmse_heading = 0, anees = 0, anees_lo = 0, anees_hi = 0, fraction_in_bounds = 0;
  double time_mean_ms = 0, time_max_ms = 0;
  std::optional<double> anis, map_nees;
  std::vector<double> time, anees_series, rmse_series;
};

/// Validates and reads a filter document; throws InputError(source, 0, field, message).
FilterRunData filter_run_from_json(const nlohmann::json& j, const std::string& source);
/// The HTML section (id "filters") with the table and the plots.
std::string filter_report_section(const std::vector<FilterRunData>& runs);

}  // namespace slamkit
