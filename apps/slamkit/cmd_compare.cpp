// slamkit compare FILE --solvers ...: every pose-graph back end from the same start, a ranked
// table, a JSON document per back end (that `slamkit report` reads) and the convergence curves
// (chi2 on a log axis against wall time) as SVG.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/core/string_list.h"
#include "slamkit/eval/plot.h"
#include "slamkit/factors/backend_comparison.h"

namespace slamkit::cli {
namespace {

struct CompareArgs {
  std::string input, solvers = "gn,lm,tr-lm,dogleg,sgd,toro,relax,mlr,hogman", init = "odometry", json, plot, format = "auto";
  double time_budget = 10.0;
  int max_iterations = 1000, threads = 1;
};

nlohmann::json to_json(const Comparison& c) {
  nlohmann::json j;
  j["kind"] = "compare";
  j["file"] = c.file;
  j["dimension"] = c.dimension;
  j["vertices"] = c.vertices;
  j["edges"] = c.edges;
  j["init"] = c.init;
  j["start_chi2"] = c.start_chi2;
  j["best_chi2"] = c.best_chi2;
  j["time_init_s"] = c.time_init_s;
  nlohmann::json runs = nlohmann::json::array();
  for (std::size_t k = 0; k < c.runs.size(); ++k) {
    const BackendRun& r = c.runs[k];
    nlohmann::json t = nlohmann::json::array();
    for (const auto& [time, chi2] : r.trace) t.push_back({time, chi2});
    runs.push_back({{"rank", k + 1},
                    {"solver", r.solver},
                    {"initial_chi2", r.initial_chi2},
                    {"final_chi2", r.final_chi2},
                    {"time_total_s", r.time_total_s},
                    {"iterations", r.iterations},
                    {"termination", r.termination},
                    {"time_to_reach_s", r.time_to_reach_s >= 0 ? nlohmann::json(r.time_to_reach_s) : nlohmann::json()},
                    {"error", r.error},
                    {"trace", std::move(t)}});
  }
  j["runs"] = std::move(runs);
  return j;
}

// What --init means, for the plot title.
std::string start_label(const std::string& init) {
  if (init == "none") return "the file's estimates";
  if (init == "zero") return "all poses at the origin";
  if (init == "auto") return "LAGO / chordal";
  return init;
}

// Both axes logarithmic: the fast solvers finish in milliseconds, the relaxers use the whole
// budget. The legend is in rank order; the curves start at each back end's first iteration.
void write_plot(const Comparison& c, const std::string& path) {
  const std::string name = std::filesystem::path(c.file).filename().string();
  Plot p(name + ": chi2 against time, every back end from " + start_label(c.init), "wall time [s] (log scale)",
         "chi2 (log scale)");
  p.set_log_y(true);
  p.set_log_x(true);
  for (std::size_t k = 0; k < c.runs.size(); ++k) {
    const BackendRun& r = c.runs[k];
    if (!r.error.empty()) continue;
    Plot::Series s;
    s.label = std::to_string(k + 1) + ". " + r.solver;
    s.color = palette(k);
    s.width = 1.8;
    s.points = r.trace.size() <= 40;
    for (const auto& [t, chi2] : r.trace) {
      s.x.push_back(t);
      s.y.push_back(chi2);
    }
    p.add_series(std::move(s));
  }
  p.add_hline(c.start_chi2, "start", Rgb{0x99, 0x99, 0x99}, "2 3");
  p.add_hline(c.best_chi2, "best found", Rgb{0x55, 0x55, 0x55});
  write_file_atomically(path, p.render(900, 520).str(), "--plot");
}

void run(const CompareArgs& a) {
  check_outputs({{&a.json, "--json"}, {&a.plot, "--plot"}});
  PoseGraphReadOptions ro;
  ro.format = parse_pose_graph_format(a.format);
  PoseGraph g = load_pose_graph(a.input, ro, nullptr);
  ComparisonOptions o;
  o.solvers = split_list(a.solvers);
  o.init = a.init;
  o.time_budget_s = a.time_budget;
  o.max_iterations = a.max_iterations;
  o.threads = a.threads;
  std::printf("slamkit compare %s: %zu vertices, %zu edges (%dD), start %s, budget %.3g s per back end\n",
              a.input.c_str(), g.vertices().size(), g.edges.size(), g.dimension(), a.init.c_str(), a.time_budget);
  const Comparison c = compare_backends(g, o);
  std::printf("\nstart chi2 %.10g (%s, %.4f s); best found %.10g\n", c.start_chi2, c.init.c_str(), c.time_init_s,
              c.best_chi2);
  std::printf("%4s %-7s %16s %12s %14s %8s  %s\n", "rank", "solver", "final chi2", "time [s]", "t(1e-3 best)",
              "iters", "termination");
  for (std::size_t k = 0; k < c.runs.size(); ++k) {
    const BackendRun& r = c.runs[k];
    char reach[32] = "-";
    if (r.time_to_reach_s >= 0) std::snprintf(reach, sizeof(reach), "%.4f", r.time_to_reach_s);
    std::printf("%4zu %-7s %16.10g %12.4f %14s %8d  %s\n", k + 1, r.solver.c_str(), r.final_chi2, r.time_total_s,
                reach, r.iterations, r.error.empty() ? r.termination.c_str() : r.error.c_str());
  }
  if (!a.json.empty()) write_json(a.json, to_json(c));
  if (!a.plot.empty()) write_plot(c, a.plot);
}

}  // namespace

void add_compare_command(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand("compare", "Run several pose-graph back ends from the same start and rank them");
  cmd->add_option("file", args->input, "Pose-graph file or sim:NAME")->required();
  cmd->add_option("--solvers", args->solvers, "Comma-separated: gn,lm,tr-lm,dogleg,sgd,toro,relax,mlr,hogman")
      ->capture_default_str();
  cmd->add_option("--init", args->init, "Start of every back end: odometry | spanning-tree | auto | zero | none")
      ->capture_default_str();
  cmd->add_option("--time-budget", args->time_budget, "Seconds per back end")->capture_default_str();
  cmd->add_option("--max-iterations", args->max_iterations, "Iterations per back end")->capture_default_str();
  cmd->add_option("--threads", args->threads, "Linearization threads of the manifold solvers")->capture_default_str();
  cmd->add_option("--format", args->format, "Input format: auto | g2o | toro | gtsam")->capture_default_str();
  cmd->add_option("--json", args->json, "Write the comparison as JSON (- for stdout); slamkit report reads it");
  cmd->add_option("--plot", args->plot, "Write the convergence curves as SVG");
  cmd->callback([args] { run(*args); });
}

}  // namespace slamkit::cli
