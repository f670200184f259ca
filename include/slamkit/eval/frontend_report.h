// DVI front-end runs in `slamkit report` (docs/frontend.md): documents of kind "frontend"
// (`slamkit frontend ... --json`: at least input, frames, static_ratio {mean, min}; optional
// camera, share_dynamic, share_flagged, frames_too_few_matches, time_per_frame_ms {mean}) and the "frontend"
// object that `slamkit vio --images --json` stores in its ATE document (frames, static_ratio,
// dynamic_precision, dynamic_recall, tracking/classification/image ms per frame). One table:
// how much of each run was flagged moving, how well against the pixel labels, and at what cost.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace slamkit {

struct FrontendRunData {
  std::string label, input, camera;
  int frames = 0;
  double static_ratio_mean = 1.0, static_ratio_min = 1.0;
  std::optional<double> share_dynamic, precision, recall, time_ms, image_ms;
  std::optional<double> share_flagged;  ///< dynamic and isolated flags / classified (since session 36)
  std::optional<long long> too_few_matches;
};

/// Reads a "frontend" object (a whole `slamkit frontend` document or the object of a vio run);
/// label names the run. Throws InputError(source, 0, field, message) on missing or malformed keys.
FrontendRunData frontend_run_from_json(const nlohmann::json& j, const std::string& label, const std::string& source);
/// The HTML section (id "frontend") with one row per run.
std::string frontend_report_section(const std::vector<FrontendRunData>& runs);

}  // namespace slamkit
