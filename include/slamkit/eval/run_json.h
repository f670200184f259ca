// The JSON document of one evaluation run (`slamkit eval ... --json`), and its reading back
// for plots and reports. Schema (all lengths in metres, angles in degrees, times in seconds):
//   kind "ate" | "rpe", schema 1, label, title, unit, pose_relation,
//   rmse, mean, median, std, min, max, sse, pairs            ← the chosen relation, top level
//   translation {rmse … sse, pairs, unit "m"}, rotation {…, unit "deg"}   ← both parts
//   alignment {mode, description, scale, rotation [[3×3]], translation [3], n_align}
//   association {method "timestamps" | "index", matched, max_diff, offset}
//   estimate / reference {path, format, poses}
//   options {align, pose_relation, t_max_diff, t_offset, n_align [, delta, delta_unit,
//            all_pairs, delta_tol, pairs_from_reference]}
//   has_timestamps, series {time [n], error [n], index [n] (sample of est_xyz/ref_xyz the
//            error is drawn at), pair_first [n] (rpe), est_xyz [[x,y,z]…] (aligned),
//            ref_xyz [[x,y,z]…] (associated)}
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamkit/eval/evaluation.h"

namespace slamkit {

/// Where the trajectories of a run came from (echoed in the JSON).
struct RunSource {
  std::string label;
  std::string est_path, est_format;
  std::string ref_path, ref_format;
  std::size_t est_poses = 0, ref_poses = 0;
};

/// evo-style title, e.g. "APE w.r.t. translation part (m) (with SE(3) Umeyama alignment)".
std::string eval_title(const EvalOptions& options);

nlohmann::json eval_result_to_json(const EvalResult& result, const RunSource& source);

/// What plots and reports use from an eval run document.
struct EvalRunData {
  std::string source;  ///< file the document came from (for messages)
  std::string kind, label, title, unit, pose_relation, align, reference;
  ErrorStatistics stats;
  std::optional<ErrorStatistics> translation, rotation;
  double scale = 1.0;
  bool has_timestamps = true;
  std::vector<double> time, error;
  std::vector<std::size_t> index;
  std::vector<Eigen::Vector3d> est_xyz, ref_xyz;
  nlohmann::json options;
};

/// Validates and reads an eval document; throws InputError(source, 0, field, message).
EvalRunData eval_run_from_json(const nlohmann::json& j, const std::string& source);

}  // namespace slamkit
