// The calibration part of `slamkit optimize` (factors/calibration_problem.h; the --calibrate
// option is parse_calibrate_option there): the printed table and the JSON fields `calibration` ([{name, value, sigma}], sigma null
// when unobservable) and, for sim:calib* inputs, `calibration_truth`.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "slamkit/factors/pose_graph_optimizer.h"

namespace slamkit::cli {

/// Prints the estimates with their sigmas (stdout) and the warnings (stderr).
void print_calibration(const CalibrationReport& report);

/// Adds `calibration_truth` to j when the input is a generated sim:calib* problem (the
/// estimates themselves come with pose_graph_result_to_json).
void add_calibration_truth_json(nlohmann::json& j, const std::string& input);

}  // namespace slamkit::cli
