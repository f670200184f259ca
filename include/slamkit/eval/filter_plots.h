// SVG plots of filter runs: trajectory and map with 3σ covariance ellipses, pose error with its
// ±3σ envelope over time, ANEES over time with its χ² bounds, time per step against the number
// of landmarks, and a dashboard of the first three for `slamkit filter --plot`.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "slamkit/eval/filter_consistency.h"
#include "slamkit/eval/svg.h"

namespace slamkit {

SvgWriter plot_filter_map(const FilterRunResult& run, const std::vector<Eigen::Vector2d>& true_landmarks,
                          const std::string& title, double width, double height);
/// Three panels (x, y, θ): error of one run and ±3σ of its covariance.
SvgWriter plot_filter_errors(const FilterRunResult& run, const std::string& title, double width, double height);
/// ANEES over time of one or more filters with the band of the first summary's bounds.
SvgWriter plot_anees(const std::vector<std::pair<std::string, const ConsistencySummary*>>& filters,
                     const std::string& title, double width, double height);
/// Pose RMSE over time of one or more filters.
SvgWriter plot_rmse(const std::vector<std::pair<std::string, const ConsistencySummary*>>& filters,
                    const std::string& title, double width, double height);

struct TimingSeries {
  std::string label;
  std::vector<double> landmarks, ms;  // time per step against map size
};
SvgWriter plot_time_per_step(const std::vector<TimingSeries>& series, const std::string& title, double width,
                             double height);

/// Map, errors, ANEES and RMSE of one filter in one document.
SvgWriter filter_dashboard(const std::string& label, const FilterRunResult& first_run,
                           const ConsistencySummary& summary, const std::vector<Eigen::Vector2d>& true_landmarks);

}  // namespace slamkit
