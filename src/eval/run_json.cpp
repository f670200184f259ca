#include "slamkit/eval/run_json.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {

namespace {

using nlohmann::json;

json stats_json(const ErrorStatistics& s) {
  return json{{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
              {"min", s.min},   {"max", s.max},   {"sse", s.sse},       {"pairs", s.count}};
}

std::string delta_text(double d) {
  std::ostringstream os;
  os << d;
  return os.str();
}

// ---- strict reading --------------------------------------------------------------------

[[noreturn]] void bad(const std::string& source, const std::string& field, const std::string& msg) {
  throw InputError(source, 0, field, msg);
}

const json& member(const json& j, const char* key, const std::string& source, const std::string& prefix = "") {
  if (!j.is_object() || !j.contains(key)) bad(source, prefix + key, "missing");
  return j.at(key);
}

double number(const json& j, const char* key, const std::string& source, const std::string& prefix = "") {
  const json& v = member(j, key, source, prefix);
  if (!v.is_number() || !std::isfinite(v.get<double>())) bad(source, prefix + key, "not a finite number");
  return v.get<double>();
}

std::string text(const json& j, const char* key, const std::string& source, const std::string& fallback) {
  if (!j.is_object() || !j.contains(key)) return fallback;
  if (!j.at(key).is_string()) bad(source, key, "not a string");
  return j.at(key).get<std::string>();
}

ErrorStatistics stats_from(const json& j, const std::string& source, const std::string& prefix) {
  ErrorStatistics s;
  s.rmse = number(j, "rmse", source, prefix);
  s.mean = number(j, "mean", source, prefix);
  s.median = number(j, "median", source, prefix);
  s.std = number(j, "std", source, prefix);
  s.min = number(j, "min", source, prefix);
  s.max = number(j, "max", source, prefix);
  s.sse = number(j, "sse", source, prefix);
  const json& n = member(j, "pairs", source, prefix);
  if (!n.is_number_unsigned()) bad(source, prefix + "pairs", "not a non-negative integer");
  s.count = n.get<std::size_t>();
  return s;
}

std::vector<double> numbers(const json& j, const char* key, const std::string& source) {
  const json& a = member(j, key, source, "series.");
  if (!a.is_array()) bad(source, std::string("series.") + key, "not an array");
  std::vector<double> out;
  out.reserve(a.size());
  for (const json& v : a) {
    if (!v.is_number()) bad(source, std::string("series.") + key, "holds a non-number");
    out.push_back(v.get<double>());
  }
  return out;
}

std::vector<Eigen::Vector3d> points(const json& j, const char* key, const std::string& source) {
  const json& a = member(j, key, source, "series.");
  if (!a.is_array()) bad(source, std::string("series.") + key, "not an array");
  std::vector<Eigen::Vector3d> out;
  out.reserve(a.size());
  for (const json& p : a) {
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
      bad(source, std::string("series.") + key, "expected [x, y, z] triples");
    out.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  }
  return out;
}

}  // namespace

std::string eval_title(const EvalOptions& o) {
  std::ostringstream os;
  const std::string unit = unit_of(o.relation);
  os << (o.kind == MetricKind::kAte ? "APE" : "RPE") << " w.r.t. " << describe(o.relation)
     << (unit.empty() ? "" : " (" + unit + ")");
  if (o.kind == MetricKind::kRpe)
    os << " for delta = " << delta_text(o.rpe.delta) << " (" << long_name(o.rpe.delta_unit) << ") using "
       << (o.rpe.all_pairs ? "all pairs" : "consecutive pairs");
  os << " (" << (o.align == AlignmentMode::kNone ? std::string("not aligned") : "with " + describe(o.align)) << ")";
  return os.str();
}

json eval_result_to_json(const EvalResult& r, const RunSource& src) {
  const EvalOptions& o = r.options;
  json j;
  j["kind"] = to_string(o.kind);
  j["schema"] = 1;
  j["label"] = src.label;
  j["title"] = eval_title(o);
  j["unit"] = unit_of(o.relation);
  j["pose_relation"] = to_string(o.relation);
  const json s = stats_json(r.stats);
  for (auto it = s.begin(); it != s.end(); ++it) j[it.key()] = it.value();
  j["translation"] = stats_json(r.translation_stats);
  j["translation"]["unit"] = "m";
  j["rotation"] = stats_json(r.rotation_stats);
  j["rotation"]["unit"] = "deg";

  json R = json::array();
  for (int row = 0; row < 3; ++row) R.push_back({r.alignment.R(row, 0), r.alignment.R(row, 1), r.alignment.R(row, 2)});
  j["alignment"] = {{"mode", to_string(o.align)},
                    {"description", describe(o.align)},
                    {"scale", r.alignment.scale},
                    {"rotation", R},
                    {"translation", {r.alignment.t.x(), r.alignment.t.y(), r.alignment.t.z()}},
                    {"n_align", o.n_align}};
  j["association"] = {{"method", r.association.by_index ? "index" : "timestamps"},
                      {"matched", r.association.size()},
                      {"max_diff", o.association.max_diff},
                      {"offset", o.association.offset}};
  j["estimate"] = {{"path", src.est_path}, {"format", src.est_format}, {"poses", src.est_poses}};
  j["reference"] = {{"path", src.ref_path}, {"format", src.ref_format}, {"poses", src.ref_poses}};
  json opt = {{"align", to_string(o.align)},
              {"pose_relation", to_string(o.relation)},
              {"t_max_diff", o.association.max_diff},
              {"t_offset", o.association.offset},
              {"n_align", o.n_align}};
  if (o.kind == MetricKind::kRpe) {
    opt["delta"] = o.rpe.delta;
    opt["delta_unit"] = to_string(o.rpe.delta_unit);
    opt["all_pairs"] = o.rpe.all_pairs;
    opt["delta_tol"] = o.rpe.rel_tol;
    opt["pairs_from_reference"] = o.rpe.pairs_from_reference;
  }
  j["options"] = opt;
  j["has_timestamps"] = r.est.has_timestamps() && r.ref.has_timestamps();

  json series;
  json time = json::array(), first = json::array();
  for (std::size_t k = 0; k < r.error_index.size(); ++k) time.push_back(r.est[r.error_index[k]].stamp);
  for (const auto& p : r.pairs) first.push_back(p.first);
  series["time"] = std::move(time);
  series["error"] = r.errors.errors;
  series["index"] = r.error_index;
  if (o.kind == MetricKind::kRpe) series["pair_first"] = std::move(first);
  json est = json::array(), ref = json::array();
  for (std::size_t k = 0; k < r.est.size(); ++k) {
    const Eigen::Vector3d& p = r.est[k].T_world_body.translation();
    const Eigen::Vector3d& q = r.ref[k].T_world_body.translation();
    est.push_back({p.x(), p.y(), p.z()});
    ref.push_back({q.x(), q.y(), q.z()});
  }
  series["est_xyz"] = std::move(est);
  series["ref_xyz"] = std::move(ref);
  j["series"] = std::move(series);
  return j;
}

EvalRunData eval_run_from_json(const json& j, const std::string& source) {
  if (!j.is_object()) bad(source, "", "an eval run must be a JSON object");
  EvalRunData d;
  d.source = source;
  d.kind = text(j, "kind", source, "");
  if (d.kind != "ate" && d.kind != "rpe") bad(source, "kind", "expected \"ate\" or \"rpe\", got \"" + d.kind + "\"");
  d.label = text(j, "label", source, std::filesystem::path(source).filename().string());
  d.title = text(j, "title", source, d.kind == "ate" ? "APE" : "RPE");
  d.unit = text(j, "unit", source, "");
  d.pose_relation = text(j, "pose_relation", source, "trans_part");
  d.stats = stats_from(j, source, "");
  if (j.contains("translation")) d.translation = stats_from(j.at("translation"), source, "translation.");
  if (j.contains("rotation")) d.rotation = stats_from(j.at("rotation"), source, "rotation.");
  if (j.contains("alignment")) {
    d.align = text(j.at("alignment"), "mode", source, "none");
    d.scale = number(j.at("alignment"), "scale", source, "alignment.");
  }
  if (j.contains("reference") && j.at("reference").is_object())
    d.reference = std::filesystem::path(text(j.at("reference"), "path", source, "")).filename().string();
  if (j.contains("has_timestamps")) {
    if (!j.at("has_timestamps").is_boolean()) bad(source, "has_timestamps", "not a boolean");
    d.has_timestamps = j.at("has_timestamps").get<bool>();
  }
  if (j.contains("options")) d.options = j.at("options");
  const json& s = member(j, "series", source);
  d.time = numbers(s, "time", source);
  d.error = numbers(s, "error", source);
  d.est_xyz = points(s, "est_xyz", source);
  d.ref_xyz = points(s, "ref_xyz", source);
  for (double v : numbers(s, "index", source)) {
    if (v < 0 || v != std::floor(v) || v >= static_cast<double>(d.est_xyz.size()))
      bad(source, "series.index", "holds a value that is not an index of est_xyz");
    d.index.push_back(static_cast<std::size_t>(v));
  }
  if (d.time.size() != d.error.size() || d.index.size() != d.error.size())
    bad(source, "series", "time, error and index must have the same length");
  if (d.est_xyz.size() != d.ref_xyz.size()) bad(source, "series", "est_xyz and ref_xyz must have the same length");
  return d;
}

}  // namespace slamkit
