#include "slamkit/eval/simulate_report.h"

#include <cmath>
#include <cstdio>

#include "slamkit/core/error.h"
#include "report_html.h"

namespace slamkit {

namespace {
using nlohmann::json;

const json& member(const json& j, const std::string& key, const std::string& source, const std::string& field) {
  if (!j.contains(key)) throw InputError(source, 0, field, "missing");
  return j.at(key);
}
double number(const json& j, const std::string& key, const std::string& source, const std::string& field) {
  const json& v = member(j, key, source, field);
  if (!v.is_number() || !std::isfinite(v.get<double>())) throw InputError(source, 0, field, "not a finite number");
  return v.get<double>();
}
const json& object(const json& j, const std::string& key, const std::string& source) {
  const json& v = member(j, key, source, key);
  if (!v.is_object()) throw InputError(source, 0, key, "not an object");
  return v;
}
std::string text(const json& j, const char* key) {
  return j.contains(key) && j.at(key).is_string() ? j.at(key).get<std::string>() : "";
}
std::string fmt(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
}  // namespace

SimulateRunData simulate_run_from_json(const json& j, const std::string& source) {
  if (!j.is_object()) throw InputError(source, 0, "", "a simulate run must be a JSON object");
  SimulateRunData d;
  d.source = text(j, "source");
  if (d.source.empty()) throw InputError(source, 0, "source", "missing or not a string");
  d.label = text(j, "output").empty() ? d.source : text(j, "output");
  d.dynamic = text(j, "dynamic");
  d.seed = static_cast<long long>(number(j, "seed", source, "seed"));
  d.duration_s = number(j, "duration_s", source, "duration_s");
  d.frames = static_cast<int>(number(j, "frames", source, "frames"));
  const json& f = object(j, "features_per_frame", source);
  d.features_mean = number(f, "mean", source, "features_per_frame.mean");
  d.features_min = number(f, "min", source, "features_per_frame.min");
  d.dynamic_share = number(j, "dynamic_share", source, "dynamic_share");
  const json& m = object(j, "static_ratio", source);
  d.static_ratio_mean = number(m, "mean", source, "static_ratio.mean");
  d.static_ratio_min = number(m, "min", source, "static_ratio.min");
  const json& fit = object(j, "spline_fit", source);
  d.fit_position_rmse_m = number(fit, "position_rmse_m", source, "spline_fit.position_rmse_m");
  d.fit_rotation_rmse_deg = number(fit, "rotation_rmse_deg", source, "spline_fit.rotation_rmse_deg");
  if (j.contains("camera") && j.at("camera").is_object()) d.camera_model = text(j.at("camera"), "model");
  if (j.contains("landmarks") && j.at("landmarks").is_object()) {
    const json& l = j.at("landmarks");
    d.static_landmarks = static_cast<int>(number(l, "static", source, "landmarks.static"));
    d.dynamic_landmarks = static_cast<int>(number(l, "dynamic", source, "landmarks.dynamic"));
    d.groups = static_cast<int>(number(l, "groups", source, "landmarks.groups"));
  }
  return d;
}

std::string simulate_report_section(const std::vector<SimulateRunData>& runs) {
  std::string h = "<section id=\"simulations\">\n<h2>Simulated visual-inertial runs</h2>\n";
  h += "<p class=\"meta\">The scenes the runs above were measured on: the real path each B-spline was fitted to "
       "(and how closely), the camera, the features per frame, and how much of what the camera saw was moving "
       "(M = static / all features of a frame).</p>\n";
  h += report_html::table_head({{"run", true}, {"path", true}, {"seed"}, {"dynamic", true}, {"camera", true},
                                {"duration [s]"}, {"frames"}, {"features/frame mean"}, {"min"}, {"dynamic share"},
                                {"M mean"}, {"M min"}, {"landmarks static / moving (groups)"}, {"fit RMSE [mm]"},
                                {"fit RMSE [deg]"}});
  using report_html::number_cell;
  using report_html::text_cell;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& r = runs[k];
    h += report_html::run_row(
        k, r.label,
        {text_cell(r.source), number_cell(std::to_string(r.seed)), text_cell(r.dynamic), text_cell(r.camera_model),
         number_cell(fmt(r.duration_s, 1)), number_cell(std::to_string(r.frames)), number_cell(fmt(r.features_mean, 1)),
         number_cell(fmt(r.features_min, 0)), number_cell(fmt(r.dynamic_share, 3)),
         number_cell(fmt(r.static_ratio_mean, 3)), number_cell(fmt(r.static_ratio_min, 3)),
         number_cell(std::to_string(r.static_landmarks) + " / " + std::to_string(r.dynamic_landmarks) + " (" +
                     std::to_string(r.groups) + ")"),
         number_cell(fmt(1e3 * r.fit_position_rmse_m, 2)), number_cell(fmt(r.fit_rotation_rmse_deg, 3))});
  }
  return h + "</table>\n</section>\n";
}

}  // namespace slamkit
