// `slamkit report`: one self-contained HTML page comparing several runs side by side.
//
// Inputs are JSON documents: eval runs ("kind": "ate" | "rpe", run_json.h), back-end
// comparisons ("kind": "compare", below), filter runs ("kind": "filter", filter_report.h) and
// optimizer summaries ("kind": "optimize"):
//   {"kind": "optimize", "label": "...", "solver": "lm", "init": "chordal", "initial_chi2": …,
//    "final_chi2": …, "iterations": …, "time_total_s": …, "termination": "...",
//    "trace": [{"iteration": 0, "cost": …, "time_s": …, …}, …]}
// where only "kind" and "trace" (each entry with a numeric "iteration" and "cost") are
// required; "time_s" is the wall time since the start of the optimization at the end of
// that iteration (entries without it are left out of the cost-vs-time plot).
// The page holds tables of statistics and inline SVG plots; CSS is inline and there are no
// scripts, fonts or images to fetch, so it renders offline. Unknown kinds and malformed
// documents throw InputError naming the file and the field.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace slamkit {

struct OptimizeRunData {
  std::string source, label, solver, init, termination;
  std::optional<double> initial_chi2, final_chi2, time_total_s;
  std::optional<long long> iterations;
  struct TraceEntry {
    double iteration = 0.0;
    double cost = 0.0;
    std::optional<double> time_s;
  };
  std::vector<TraceEntry> trace;
};

/// Validates and reads an optimizer summary; throws InputError(source, 0, field, message).
OptimizeRunData optimize_run_from_json(const nlohmann::json& j, const std::string& source);

/// The back ends of a comparison (`slamkit compare --json`: {"kind": "compare", "file", "init",
/// "runs": [{"solver", "final_chi2", "time_total_s", "iterations", "trace": [[time_s, chi2], …]}]}),
/// one optimizer run each, so the report shows them in its table and cost curves.
std::vector<OptimizeRunData> compare_runs_from_json(const nlohmann::json& j, const std::string& source);

struct ReportInput {
  std::string path;        ///< shown in the page and in error messages
  nlohmann::json document;
};

struct ReportOptions {
  std::string title = "slamkit evaluation report";
  std::string generator = "slamkit";  ///< e.g. "slamkit 0.1.0", shown in the footer
};

/// The complete HTML page. Throws InputError for unknown kinds or malformed documents.
std::string render_html_report(const std::vector<ReportInput>& inputs, const ReportOptions& options);

}  // namespace slamkit
