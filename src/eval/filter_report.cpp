#include "slamkit/eval/filter_report.h"

#include <cmath>
#include <cstdio>
#include <map>

#include "slamkit/core/error.h"
#include "slamkit/eval/plot.h"
#include "report_html.h"

namespace slamkit {

namespace {
using nlohmann::json;

double number(const json& j, const char* key, const std::string& source) {
  if (!j.contains(key) || !j.at(key).is_number()) throw InputError(source, 0, key, "missing or not a number");
  return j.at(key).get<double>();
}
std::optional<double> optional_number(const json& j, const char* key, const std::string& source) {
  if (!j.contains(key) || j.at(key).is_null()) return std::nullopt;
  if (!j.at(key).is_number()) throw InputError(source, 0, key, "not a number");
  return j.at(key).get<double>();
}
std::string text(const json& j, const char* key) {
  return j.contains(key) && j.at(key).is_string() ? j.at(key).get<std::string>() : "";
}
std::vector<double> series(const json& j, const char* key, const std::string& source) {
  std::vector<double> v;
  if (!j.contains("series") || !j.at("series").is_object() || !j.at("series").contains(key)) return v;
  const json& a = j.at("series").at(key);
  if (!a.is_array()) throw InputError(source, 0, std::string("series.") + key, "not an array");
  for (const auto& x : a) {
    if (!x.is_number()) throw InputError(source, 0, std::string("series.") + key, "not a number");
    v.push_back(x.get<double>());
  }
  return v;
}
std::string fmt(double v, int decimals) { return report_html::fixed(v, decimals); }
}  // namespace

FilterRunData filter_run_from_json(const json& j, const std::string& source) {
  if (!j.is_object()) throw InputError(source, 0, "", "a filter run must be a JSON object");
  FilterRunData d;
  d.source = source;
  d.algorithm = text(j, "algorithm");
  d.label = text(j, "label").empty() ? d.algorithm : text(j, "label");
  d.world = text(j, "world");
  d.association = text(j, "association");
  d.runs = int(number(j, "runs", source));
  d.landmarks = int(number(j, "landmarks", source));
  d.active = j.contains("active") && j.at("active").is_number() ? j.at("active").get<int>() : 0;
  d.rmse_position = number(j, "rmse_position", source);
  d.rmse_heading = number(j, "rmse_heading", source);
  d.anees = number(j, "anees", source);
  if (!j.contains("anees_bounds") || !j.at("anees_bounds").is_array() || j.at("anees_bounds").size() != 2 ||
      !j.at("anees_bounds")[0].is_number() || !j.at("anees_bounds")[1].is_number())
    throw InputError(source, 0, "anees_bounds", "must be [lo, hi]");
  d.anees_lo = j.at("anees_bounds")[0].get<double>();
  d.anees_hi = j.at("anees_bounds")[1].get<double>();
  d.fraction_in_bounds = number(j, "fraction_in_bounds", source);
  if (!j.contains("time_per_step_ms") || !j.at("time_per_step_ms").is_object())
    throw InputError(source, 0, "time_per_step_ms", "missing: expected {mean, max}");
  d.time_mean_ms = number(j.at("time_per_step_ms"), "mean", source);
  d.time_max_ms = number(j.at("time_per_step_ms"), "max", source);
  d.anis = optional_number(j, "anis", source);
  d.map_nees = optional_number(j, "map_nees", source);
  d.time = series(j, "time", source);
  d.anees_series = series(j, "anees", source);
  d.rmse_series = series(j, "rmse_position", source);
  return d;
}

std::string filter_report_section(const std::vector<FilterRunData>& runs) {
  std::string h = "<section id=\"filters\">\n<h2>Landmark-SLAM filters</h2>\n";
  h += "<p class=\"meta\">Pose RMSE over all runs and steps; ANEES = mean over time of the pose NEES averaged "
       "over the runs (3 dof), with its two-sided 95% χ² bounds; in bounds = share of steps whose ANEES lies inside.</p>\n";
  h += report_html::table_head({{"run", true}, {"world", true}, {"association", true}, {"runs"}, {"landmarks"},
                                {"RMSE pos. [m]"}, {"RMSE head. [deg]"}, {"ANEES"}, {"bounds"}, {"in bounds"},
                                {"ANIS"}, {"map NEES"}, {"ms/step mean"}, {"ms/step max"}});
  std::map<std::string, double> best;  // per world: lowest RMSE
  for (const auto& r : runs) {
    auto it = best.find(r.world);
    if (it == best.end() || r.rmse_position < it->second) best[r.world] = r.rmse_position;
  }
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& r = runs[k];
    const bool is_best = runs.size() > 1 && r.rmse_position == best[r.world];
    const bool consistent = r.anees >= r.anees_lo && r.anees <= r.anees_hi;
    using report_html::number_cell;
    using report_html::text_cell;
    h += report_html::run_row(
        k, r.label,
        {text_cell(r.world), text_cell(r.association), number_cell(std::to_string(r.runs)),
         number_cell(std::to_string(r.landmarks)), number_cell(fmt(r.rmse_position, 3), is_best),
         number_cell(fmt(r.rmse_heading, 3)), number_cell(fmt(r.anees, 2), consistent),
         number_cell("[" + fmt(r.anees_lo, 3) + ", " + fmt(r.anees_hi, 3) + "]"),
         number_cell(fmt(100 * r.fraction_in_bounds, 1) + "%"), number_cell(r.anis ? fmt(*r.anis, 2) : "–"),
         number_cell(r.map_nees ? fmt(*r.map_nees, 2) : "–"), number_cell(fmt(r.time_mean_ms, 4)),
         number_cell(fmt(r.time_max_ms, 3))});
  }
  h += "</table>\n";
  std::map<std::string, std::vector<std::size_t>> by_world;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (!runs[k].time.empty()) by_world[runs[k].world].push_back(k);
  for (const auto& [world, idx] : by_world) {
    Plot anees("ANEES over time: " + world, "time [s]", "ANEES (log scale)");
    anees.set_log_y(true);
    Plot rmse("Position RMSE over time: " + world, "time [s]", "RMSE [m]");
    rmse.set_y_from_zero(true);
    const auto& first = runs[idx.front()];
    anees.add_band(first.anees_lo, first.anees_hi, "95% bounds", Rgb{60, 160, 60}, 0.18);
    for (std::size_t k : idx) {
      Plot::Series s;
      s.label = runs[k].label;
      s.color = palette(k);
      s.width = 1.4;
      s.x = runs[k].time;
      s.y = runs[k].anees_series;
      if (s.y.size() == s.x.size()) anees.add_series(s);
      s.y = runs[k].rmse_series;
      if (s.y.size() == s.x.size()) rmse.add_series(s);
    }
    h += "<div class=\"grid\">\n<figure>" + anees.render(610, 420).str() + "</figure>\n<figure>" +
         rmse.render(610, 420).str() + "</figure>\n</div>\n";
  }
  return h + "</section>\n";
}

}  // namespace slamkit
