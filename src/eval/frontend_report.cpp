#include "slamkit/eval/frontend_report.h"

#include <cmath>
#include <cstdio>

#include "slamkit/core/error.h"
#include "report_html.h"

namespace slamkit {

namespace {
using nlohmann::json;

double number(const json& j, const std::string& key, const std::string& source, const std::string& field) {
  if (!j.contains(key)) throw InputError(source, 0, field, "missing");
  const json& v = j.at(key);
  if (!v.is_number() || !std::isfinite(v.get<double>())) throw InputError(source, 0, field, "not a finite number");
  return v.get<double>();
}
std::optional<double> optional(const json& j, const std::string& key, const std::string& source, const std::string& field) {
  if (!j.contains(key)) return std::nullopt;
  return number(j, key, source, field);
}
std::string text(const json& j, const char* key) {
  return j.contains(key) && j.at(key).is_string() ? j.at(key).get<std::string>() : "";
}
std::string fmt(const std::optional<double>& v, int decimals, double scale = 1.0) {
  if (!v) return "–";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, *v * scale);
  return buf;
}
}  // namespace

FrontendRunData frontend_run_from_json(const json& j, const std::string& label, const std::string& source) {
  if (!j.is_object()) throw InputError(source, 0, "frontend", "a front-end run must be a JSON object");
  FrontendRunData d;
  d.label = label;
  d.input = text(j, "input").empty() ? text(j, "image_source") : text(j, "input");
  d.camera = j.contains("camera") && j.at("camera").is_string() ? j.at("camera").get<std::string>() : "";
  d.frames = static_cast<int>(number(j, "frames", source, "frames"));
  if (!j.contains("static_ratio") || !j.at("static_ratio").is_object())
    throw InputError(source, 0, "static_ratio", "missing or not an object");
  d.static_ratio_mean = number(j.at("static_ratio"), "mean", source, "static_ratio.mean");
  d.static_ratio_min = number(j.at("static_ratio"), "min", source, "static_ratio.min");
  d.share_dynamic = optional(j, "share_dynamic", source, "share_dynamic");
  d.share_flagged = optional(j, "share_flagged", source, "share_flagged");
  d.precision = optional(j, "dynamic_precision", source, "dynamic_precision");
  d.recall = optional(j, "dynamic_recall", source, "dynamic_recall");
  if (j.contains("time_per_frame_ms") && j.at("time_per_frame_ms").is_object())
    d.time_ms = number(j.at("time_per_frame_ms"), "mean", source, "time_per_frame_ms.mean");
  else if (j.contains("tracking_ms_per_frame"))
    d.time_ms = number(j, "tracking_ms_per_frame", source, "tracking_ms_per_frame") +
                number(j, "classification_ms_per_frame", source, "classification_ms_per_frame");
  d.image_ms = optional(j, "image_ms_per_frame", source, "image_ms_per_frame");
  if (const auto n = optional(j, "frames_too_few_matches", source, "frames_too_few_matches"))
    d.too_few_matches = static_cast<long long>(*n);
  return d;
}

std::string frontend_report_section(const std::vector<FrontendRunData>& runs) {
  std::string h = "<section id=\"frontend\">\n<h2>DVI front end</h2>\n";
  h += "<p class=\"meta\">Features tracked by KLT and classified by the epipolar test (docs/frontend.md): "
       "M = static / classified features of a frame; the dynamic share counts the flags in groups, the flagged "
       "share also the isolated ones (a flag with no other near it: no moving object claimed); precision and "
       "recall of \"dynamic\" against the rendered pixel labels where the run has them; time of tracking + "
       "classification per frame, image time (rendering or reading) apart.</p>\n";
  h += report_html::table_head({{"run", true}, {"input", true}, {"frames"}, {"M mean"}, {"M min"},
                                {"dynamic share [%]"}, {"flagged share [%]"}, {"precision"}, {"recall"}, {"frames &lt; 8 matches"},
                                {"front end [ms/frame]"}, {"images [ms/frame]"}});
  using report_html::number_cell;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const FrontendRunData& r = runs[k];
    h += report_html::run_row(
        k, r.label,
        {report_html::text_cell(r.input), number_cell(std::to_string(r.frames)), number_cell(fmt(r.static_ratio_mean, 3)),
         number_cell(fmt(r.static_ratio_min, 3)), number_cell(fmt(r.share_dynamic, 1, 100.0)),
         number_cell(fmt(r.share_flagged, 1, 100.0)), number_cell(fmt(r.precision, 3)), number_cell(fmt(r.recall, 3)),
         number_cell(r.too_few_matches ? std::to_string(*r.too_few_matches) : "–"), number_cell(fmt(r.time_ms, 1)),
         number_cell(fmt(r.image_ms, 1))});
  }
  h += "</table>\n</section>\n";
  return h;
}

}  // namespace slamkit
