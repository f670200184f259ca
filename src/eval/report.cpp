#include "slamkit/eval/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "slamkit/core/error.h"
#include "slamkit/eval/eval_plots.h"
#include "slamkit/eval/filter_report.h"
#include "slamkit/eval/frontend_report.h"
#include "slamkit/eval/simulate_report.h"
#include "slamkit/eval/plot.h"
#include "slamkit/eval/run_json.h"
#include "report_html.h"

namespace slamkit {

namespace {

using nlohmann::json;

constexpr double kHalf = 610;  // width of a half-row figure [px]
constexpr double kFull = 1232;

const char* kCss = R"(
body { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; color: #222; background: #f4f5f7;
       margin: 0; }
main { max-width: 1260px; margin: 0 auto; padding: 20px 14px 40px; }
h1 { font-size: 24px; margin: 8px 0 4px; }
h2 { font-size: 19px; margin: 30px 0 10px; border-bottom: 2px solid #d0d4da; padding-bottom: 4px; }
h3 { font-size: 15px; margin: 18px 0 8px; color: #333; }
p.meta { color: #555; margin: 0 0 12px; font-size: 13px; }
nav a { margin-right: 14px; font-size: 13px; color: #1f5fa8; }
table { border-collapse: collapse; background: #fff; font-size: 12.5px; margin: 6px 0 14px;
        box-shadow: 0 1px 2px rgba(0,0,0,.08); }
th, td { padding: 5px 9px; border-bottom: 1px solid #e3e5e8; text-align: right; white-space: nowrap; }
th { background: #eceef1; font-weight: 600; }
td.text, th.text { text-align: left; }
td.best { font-weight: 700; color: #0b6b2d; }
.swatch { display: inline-block; width: 10px; height: 10px; border-radius: 2px; margin-right: 6px; }
.grid { display: flex; flex-wrap: wrap; gap: 12px; }
figure { margin: 0; background: #fff; border: 1px solid #dde0e4; border-radius: 4px; padding: 0;
         box-shadow: 0 1px 2px rgba(0,0,0,.06); }
figure svg { display: block; }
footer { color: #777; font-size: 12px; margin-top: 28px; }
code { font-size: 12px; }
)";

std::string esc(const std::string& s) { return xml_escape(s); }

std::string fixed(double v, int decimals = 4) { return report_html::fixed(v, decimals); }
using report_html::number_cell;
using report_html::text_cell;

std::string general(double v) {
  if (!std::isfinite(v)) return "–";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string figure(const SvgWriter& svg) { return "<figure>" + svg.str() + "</figure>\n"; }

// ---- optimizer documents ---------------------------------------------------------------

std::optional<double> opt_number(const json& j, const char* key, const std::string& source) {
  if (!j.contains(key) || j.at(key).is_null()) return std::nullopt;
  if (!j.at(key).is_number()) throw InputError(source, 0, key, "not a number");
  return j.at(key).get<double>();
}

std::string opt_text(const json& j, const char* key, const std::string& source) {
  if (!j.contains(key) || j.at(key).is_null()) return "";
  if (!j.at(key).is_string()) throw InputError(source, 0, key, "not a string");
  return j.at(key).get<std::string>();
}

// ---- sections --------------------------------------------------------------------------

std::string eval_table(const std::vector<EvalRunData>& runs) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& r : runs) best = std::min(best, r.stats.rmse);
  const std::string unit = runs.front().unit.empty() ? "" : " [" + runs.front().unit + "]";
  std::string h = report_html::table_head({{"run", true}, {"reference", true}, {"alignment", true}, {"scale"},
                                          {"pairs"}, {"rmse" + unit}, {"mean"}, {"median"}, {"std"}, {"min"},
                                          {"max"}, {"trans. rmse [m]"}, {"rot. rmse [deg]"}});
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const EvalRunData& r = runs[k];
    const bool is_best = runs.size() > 1 && r.stats.rmse == best;
    h += report_html::run_row(
        k, r.label,
        {text_cell(r.reference), text_cell(r.align), number_cell(general(r.scale)),
         number_cell(std::to_string(r.stats.count)), number_cell(fixed(r.stats.rmse), is_best),
         number_cell(fixed(r.stats.mean)), number_cell(fixed(r.stats.median)), number_cell(fixed(r.stats.std)),
         number_cell(fixed(r.stats.min)), number_cell(fixed(r.stats.max)),
         number_cell(r.translation ? fixed(r.translation->rmse) : "–"),
         number_cell(r.rotation ? fixed(r.rotation->rmse) : "–")});
  }
  return h + "</table>\n";
}

std::string eval_section(const std::string& id, const std::string& heading, const std::vector<EvalRunData>& runs) {
  std::string h = "<section id=\"" + id + "\">\n<h2>" + esc(heading) + "</h2>\n";
  std::vector<std::string> titles;
  for (const auto& r : runs)
    if (std::find(titles.begin(), titles.end(), r.title) == titles.end()) titles.push_back(r.title);
  for (const auto& t : titles) h += "<p class=\"meta\">" + esc(t) + "</p>\n";
  h += eval_table(runs);

  // Trajectory overlays, one pair of views per reference (runs on different datasets).
  std::map<std::string, std::vector<const EvalRunData*>> by_reference;
  for (const auto& r : runs) by_reference[r.reference + "#" + std::to_string(r.ref_xyz.size())].push_back(&r);
  for (const auto& [key, group] : by_reference) {
    h += "<h3>Trajectories vs " + esc(group.front()->reference.empty() ? "reference" : group.front()->reference) +
         "</h3>\n<div class=\"grid\">\n" + figure(plot_trajectories(group, TrajectoryView::kTop, kHalf, 480)) +
         figure(plot_trajectories(group, TrajectoryView::kSide, kHalf, 480)) + "</div>\n";
  }
  h += "<h3>Error along the path</h3>\n<div class=\"grid\">\n";
  for (const auto& r : runs) h += figure(plot_error_along_path(r, kHalf, 480));
  h += "</div>\n";

  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
  for (const auto& r : runs) {
    names.push_back(r.label);
    values.push_back({r.stats.rmse, r.stats.mean, r.stats.median, r.stats.max});
  }
  BarChart bars("Statistics per run", runs.front().unit.empty() ? "error" : "error [" + runs.front().unit + "]",
                names, {"rmse", "mean", "median", "max"});
  bars.set_values(values);
  std::vector<Rgb> colors;
  for (std::size_t k = 0; k < runs.size(); ++k) colors.push_back(palette(k));
  bars.set_category_colors(colors);
  std::vector<const EvalRunData*> all;
  for (const auto& r : runs) all.push_back(&r);
  h += "<h3>Error statistics</h3>\n<div class=\"grid\">\n" + figure(bars.render(kHalf, 400)) +
       figure(plot_error_histogram(all, kHalf, 400)) + figure(plot_error_over_time(all, kFull, 340));
  return h + "</div>\n</section>\n";
}

std::string optimize_section(const std::vector<OptimizeRunData>& runs) {
  std::string h = "<section id=\"optimize\">\n<h2>Optimization</h2>\n";
  double best = std::numeric_limits<double>::infinity();
  for (const auto& r : runs)
    if (r.final_chi2) best = std::min(best, *r.final_chi2);
  h += report_html::table_head({{"run", true}, {"solver", true}, {"init", true}, {"iterations"}, {"initial χ²"},
                                {"final χ²"}, {"time [s]"}, {"termination", true}});
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const OptimizeRunData& r = runs[k];
    const bool is_best = runs.size() > 1 && r.final_chi2 && *r.final_chi2 == best;
    h += report_html::run_row(
        k, r.label,
        {text_cell(r.solver), text_cell(r.init), number_cell(r.iterations ? std::to_string(*r.iterations) : "–"),
         number_cell(r.initial_chi2 ? general(*r.initial_chi2) : "–"),
         number_cell(r.final_chi2 ? general(*r.final_chi2) : "–", is_best),
         number_cell(r.time_total_s ? fixed(*r.time_total_s, 3) : "–"), text_cell(r.termination)});
  }
  h += "</table>\n";
  Plot by_iter("Cost per iteration", "iteration", "cost (log scale)");
  Plot by_time("Cost over time", "time [s]", "cost (log scale)");
  by_iter.set_log_y(true);
  by_time.set_log_y(true);
  for (std::size_t k = 0; k < runs.size(); ++k) {
    Plot::Series it, tm;
    it.label = tm.label = runs[k].label;
    it.color = tm.color = palette(k);
    it.width = tm.width = 1.8;
    it.points = tm.points = runs[k].trace.size() <= 60;
    for (const auto& e : runs[k].trace) {
      it.x.push_back(e.iteration);
      it.y.push_back(e.cost);
      if (e.time_s) tm.x.push_back(*e.time_s), tm.y.push_back(e.cost);
    }
    by_iter.add_series(std::move(it));
    if (!tm.x.empty()) by_time.add_series(std::move(tm));
  }
  h += "<div class=\"grid\">\n" + figure(by_iter.render(kHalf, 420)) + figure(by_time.render(kHalf, 420)) + "</div>\n";
  return h + "</section>\n";
}

}  // namespace

OptimizeRunData optimize_run_from_json(const json& j, const std::string& source) {
  if (!j.is_object()) throw InputError(source, 0, "", "an optimizer summary must be a JSON object");
  OptimizeRunData d;
  d.source = source;
  d.label = opt_text(j, "label", source);
  if (d.label.empty()) d.label = std::filesystem::path(source).filename().string();
  d.solver = opt_text(j, "solver", source);
  d.init = opt_text(j, "init", source);
  d.termination = opt_text(j, "termination", source);
  d.initial_chi2 = opt_number(j, "initial_chi2", source);
  d.final_chi2 = opt_number(j, "final_chi2", source);
  d.time_total_s = opt_number(j, "time_total_s", source);
  if (j.contains("iterations") && !j.at("iterations").is_null()) {
    if (!j.at("iterations").is_number_integer()) throw InputError(source, 0, "iterations", "not an integer");
    d.iterations = j.at("iterations").get<long long>();
  }
  if (!j.contains("trace")) throw InputError(source, 0, "trace", "missing");
  const json& trace = j.at("trace");
  if (!trace.is_array()) throw InputError(source, 0, "trace", "not an array");
  for (std::size_t k = 0; k < trace.size(); ++k) {
    const json& e = trace[k];
    const std::string field = "trace[" + std::to_string(k) + "]";
    if (!e.is_object()) throw InputError(source, 0, field, "not an object");
    OptimizeRunData::TraceEntry t;
    const auto it = opt_number(e, "iteration", source);
    const auto cost = opt_number(e, "cost", source);
    if (!it) throw InputError(source, 0, field + ".iteration", "missing");
    if (!cost) throw InputError(source, 0, field + ".cost", "missing");
    if (!std::isfinite(*it) || !std::isfinite(*cost)) throw InputError(source, 0, field, "not finite");
    t.iteration = *it;
    t.cost = *cost;
    t.time_s = opt_number(e, "time_s", source);
    d.trace.push_back(t);
  }
  return d;
}

std::vector<OptimizeRunData> compare_runs_from_json(const json& j, const std::string& source) {
  if (!j.contains("runs") || !j.at("runs").is_array()) throw InputError(source, 0, "runs", "missing or not an array");
  const std::string file = opt_text(j, "file", source);
  std::vector<OptimizeRunData> out;
  const json& runs = j.at("runs");
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const json& r = runs[k];
    const std::string field = "runs[" + std::to_string(k) + "]";
    if (!r.is_object()) throw InputError(source, 0, field, "not an object");
    OptimizeRunData d;
    d.source = source;
    d.solver = opt_text(r, "solver", source);
    if (d.solver.empty()) throw InputError(source, 0, field + ".solver", "missing");
    d.label = d.solver + (file.empty() ? "" : " on " + std::filesystem::path(file).filename().string());
    d.init = opt_text(j, "init", source);
    d.termination = opt_text(r, "termination", source);
    d.initial_chi2 = opt_number(r, "initial_chi2", source);
    d.final_chi2 = opt_number(r, "final_chi2", source);
    d.time_total_s = opt_number(r, "time_total_s", source);
    if (r.contains("iterations") && r.at("iterations").is_number_integer()) d.iterations = r.at("iterations").get<long long>();
    if (!r.contains("trace") || !r.at("trace").is_array()) throw InputError(source, 0, field + ".trace", "missing or not an array");
    const json& trace = r.at("trace");
    for (std::size_t i = 0; i < trace.size(); ++i) {
      const json& e = trace[i];
      if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number())
        throw InputError(source, 0, field + ".trace[" + std::to_string(i) + "]", "expected [time_s, chi2]");
      OptimizeRunData::TraceEntry t;
      t.iteration = static_cast<double>(i);
      t.time_s = e[0].get<double>();
      t.cost = e[1].get<double>();
      if (!std::isfinite(*t.time_s) || !std::isfinite(t.cost))
        throw InputError(source, 0, field + ".trace[" + std::to_string(i) + "]", "not finite");
      d.trace.push_back(t);
    }
    out.push_back(std::move(d));
  }
  return out;
}

std::string render_html_report(const std::vector<ReportInput>& inputs, const ReportOptions& options) {
  if (inputs.empty()) throw InputError("", 0, "", "report: no input runs");
  // Eval runs are grouped by metric and pose relation, so one table/axis never mixes units.
  std::vector<std::pair<std::string, std::vector<EvalRunData>>> groups;  // key "ate:trans_part"
  std::vector<OptimizeRunData> opt;
  std::vector<FilterRunData> filt;
  std::vector<SimulateRunData> sims;
  std::vector<FrontendRunData> fronts;  // slamkit frontend --json, and vio --images runs' "frontend"
  std::size_t n_ate = 0, n_rpe = 0;
  for (const auto& in : inputs) {
    const json& j = in.document;
    if (!j.is_object() || !j.contains("kind") || !j.at("kind").is_string())
      throw InputError(in.path, 0, "kind", "missing: expected \"ate\", \"rpe\", \"optimize\", \"compare\", \"filter\", \"simulate\" or \"frontend\"");
    const std::string kind = j.at("kind").get<std::string>();
    if (kind == "ate" || kind == "rpe") {
      EvalRunData d = eval_run_from_json(j, in.path);
      if (j.contains("frontend")) fronts.push_back(frontend_run_from_json(j.at("frontend"), d.label, in.path));
      (kind == "ate" ? n_ate : n_rpe) += 1;
      const std::string key = kind + ":" + d.pose_relation;
      auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.first == key; });
      if (g == groups.end()) g = groups.insert(groups.end(), {key, {}});
      g->second.push_back(std::move(d));
    } else if (kind == "optimize") {
      opt.push_back(optimize_run_from_json(j, in.path));
    } else if (kind == "compare") {  // one optimizer run per back end (slamkit compare --json)
      for (OptimizeRunData& d : compare_runs_from_json(j, in.path)) opt.push_back(std::move(d));
    } else if (kind == "filter") {  // slamkit filter --json
      filt.push_back(filter_run_from_json(j, in.path));
    } else if (kind == "simulate") {  // slamkit simulate --vi ... --json
      sims.push_back(simulate_run_from_json(j, in.path));
    } else if (kind == "frontend") {  // slamkit frontend --json
      fronts.push_back(frontend_run_from_json(j, opt_text(j, "input", in.path), in.path));
    } else {
      throw InputError(in.path, 0, "kind", "unknown kind \"" + kind + "\" (expected ate, rpe, optimize, compare, filter, simulate or frontend)");
    }
  }
  // APE sections first, then RPE, each in order of first appearance.
  std::stable_sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) {
    return a.first.compare(0, 3, "ate") == 0 && b.first.compare(0, 3, "ate") != 0;
  });
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                  "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
                  esc(options.title) + "</title>\n<style>" + kCss + "</style>\n</head>\n<body>\n<main>\n";
  std::string counts;
  for (const auto& [n, what] : {std::pair<std::size_t, const char*>{n_ate, " APE"}, {n_rpe, " RPE"},
                                {opt.size(), " optimization"}, {filt.size(), " filter"},
                                {sims.size(), " simulation"}, {fronts.size(), " front-end"}})
    if (n > 0) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + what;
  h += "<h1>" + esc(options.title) + "</h1>\n<p class=\"meta\">" + std::to_string(inputs.size()) + " run" +
       (inputs.size() == 1 ? "" : "s") + ": " + counts + "</p>\n<nav>";
  std::string sections;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto& runs = groups[g].second;
    const bool ate = runs.front().kind == "ate";
    const std::string id = (ate ? "ate" : "rpe") + (g == 0 || groups[g - 1].second.front().kind != runs.front().kind
                                                        ? std::string()
                                                        : "-" + std::to_string(g));
    const std::string unit = runs.front().unit.empty() ? "" : " [" + runs.front().unit + "]";
    const std::string what = runs.front().pose_relation == "trans_part" ? "" : ", " + runs.front().pose_relation + unit;
    const std::string name = ate ? "Absolute pose error" : "Relative pose error";
    h += "<a href=\"#" + id + "\">" + esc(name + what) + "</a>";
    sections += eval_section(id, name + (ate ? " (APE / ATE)" : " (RPE)") + what, runs);
  }
  if (!opt.empty()) h += "<a href=\"#optimize\">Optimization</a>";
  if (!filt.empty()) h += "<a href=\"#filters\">Filters</a>";
  if (!sims.empty()) h += "<a href=\"#simulations\">Simulations</a>";
  if (!fronts.empty()) h += "<a href=\"#frontend\">Front end</a>";
  h += "</nav>\n" + sections;
  if (!opt.empty()) h += optimize_section(opt);
  if (!filt.empty()) h += filter_report_section(filt);
  if (!sims.empty()) h += simulate_report_section(sims);
  if (!fronts.empty()) h += frontend_report_section(fronts);
  h += "<footer>Generated by " + esc(options.generator) + " from:<br>";
  for (const auto& in : inputs) h += "<code>" + esc(in.path) + "</code><br>";
  h += "</footer>\n</main>\n</body>\n</html>\n";
  return h;
}

}  // namespace slamkit
