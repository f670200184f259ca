// slamkit optimize FILE: initialize and optimize a pose graph, print progress and a summary.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "optimize_hogman.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/io/trajectory_io.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit::cli {
namespace {

struct OptimizeArgs {
  std::string input, output, json, trajectory, config, label;
  std::string solver = "gn", init = "auto", robust, format = "auto", linear_solver = "auto", ordering = "auto";
  int max_iterations = 100, threads = 0, blas_threads = 1;
  double function_tolerance = 1e-5, gradient_tolerance = 1e-10, parameter_tolerance = 1e-8;
  bool robust_loops_only = false, repair_information = false, allow_unknown_tags = false, quiet = false;
};

// Options from a JSON config file; command-line flags given explicitly win.
void apply_config(const std::string& path, const CLI::App& cmd, OptimizeArgs& a) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot open config file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("not valid JSON: ") + e.what());
  }
  auto take = [&](const char* key, const char* flag, auto& field) {
    if (!j.contains(key) || cmd.count(flag) > 0) return;
    try {
      j.at(key).get_to(field);
    } catch (const nlohmann::json::exception&) {
      throw InputError(path, 0, key, "has the wrong type");
    }
  };
  for (auto it = j.begin(); it != j.end(); ++it) {
    static const char* known[] = {"solver", "init", "robust", "robust_loop_closures_only", "max_iterations", "threads",
                                  "blas_threads", "function_tolerance", "gradient_tolerance", "parameter_tolerance",
                                  "linear_solver", "ordering", "repair_information", "format"};
    if (std::find(std::begin(known), std::end(known), it.key()) == std::end(known))
      throw InputError(path, 0, it.key(), "unknown option");
  }
  take("solver", "--solver", a.solver);
  take("init", "--init", a.init);
  take("robust", "--robust", a.robust);
  take("robust_loop_closures_only", "--robust-loop-closures-only", a.robust_loops_only);
  take("max_iterations", "--max-iterations", a.max_iterations);
  take("threads", "--threads", a.threads);
  take("blas_threads", "--blas-threads", a.blas_threads);
  take("function_tolerance", "--function-tolerance", a.function_tolerance);
  take("gradient_tolerance", "--gradient-tolerance", a.gradient_tolerance);
  take("parameter_tolerance", "--parameter-tolerance", a.parameter_tolerance);
  take("linear_solver", "--linear-solver", a.linear_solver);
  take("ordering", "--ordering", a.ordering);
  take("repair_information", "--repair-information", a.repair_information);
  take("format", "--format", a.format);
}

PoseGraph load(const OptimizeArgs& a, PoseGraphReadReport* report) {
  PoseGraphReadOptions ro;
  ro.format = parse_pose_graph_format(a.format);
  ro.repair_information = a.repair_information;
  ro.unknown_tags_as_warnings = a.allow_unknown_tags;
  return load_pose_graph(a.input, ro, report);
}

void run(const CLI::App& cmd, OptimizeArgs a) {
  if (!a.config.empty()) apply_config(a.config, cmd, a);
  if (a.solver == "hogman") {  // the hierarchical back end (optimize_hogman.cpp)
    PoseGraph g = load(a, nullptr);
    return run_hogman_optimize(g, {a.input, a.json, a.output, a.trajectory, a.label, a.quiet, a.threads > 0 ? a.threads : 1});
  }
  PoseGraphOptimizerOptions o;
  o.init = parse_init_method(a.init);
  o.optimizer.algorithm = parse_algorithm(a.solver);
  o.optimizer.max_iterations = a.max_iterations;
  o.optimizer.num_threads = a.threads;
  o.optimizer.blas_threads = a.blas_threads;
  o.optimizer.function_tolerance = a.function_tolerance;
  o.optimizer.gradient_tolerance = a.gradient_tolerance;
  o.optimizer.parameter_tolerance = a.parameter_tolerance;
  o.optimizer.linear_solver = parse_sparse_backend(a.linear_solver);
  o.optimizer.ordering = parse_ordering(a.ordering);
  if (!a.robust.empty()) o.problem.kernel = parse_robust_kernel(a.robust);
  o.problem.kernel_on_odometry = !a.robust_loops_only;

  const Stopwatch load_clock;
  PoseGraphReadReport report;
  PoseGraph g = load(a, &report);
  const double load_time = load_clock.seconds();
  for (const std::string& w : report.warnings) std::cerr << "slamkit: warning: " << w << "\n";
  if (report.repaired_information > 0)
    std::cerr << "slamkit: note: projected " << report.repaired_information
              << " information matrices to the PSD cone (--repair-information)\n";

  if (!a.quiet) {
    std::printf("slamkit optimize %s: %zu vertices, %zu edges (%dD), loaded in %.4f s\n", a.input.c_str(),
                g.vertices().size(), g.edges.size(), g.dimension(), load_time);
    o.optimizer.callback = [&](const IterationSummary& it) {
      if (it.iteration == 0) std::printf("%s\n", Summary::progress_header().c_str());
      std::printf("%s\n", Summary::progress_line(it, o.optimizer.algorithm).c_str());
      std::fflush(stdout);
      return true;
    };
  }
  std::vector<std::string> gauge_notes;  // the pipeline makes the same choice; say it up front
  gauge_vertices(g, &gauge_notes);
  for (const std::string& n : gauge_notes) std::cerr << "slamkit: note: " << n << "\n";
  const PoseGraphResult r = optimize_pose_graph(g, o);

  std::printf("%s", r.summary.report().c_str());
  std::printf("  initialization   %s: chi2 %.10g -> %.10g in %.4f s\n", to_string(r.init.used), r.input_chi2,
              r.chi2_after_init, r.init.time_s);
  std::printf("  result           chi2 %.10g (g2o definition), end-to-end %.4f s (init + optimization; load %.4f s "
              "apart)\n",
              r.final_chi2, r.time_total_s, load_time);

  if (!a.output.empty()) {
    std::vector<std::string> warnings;
    write_pose_graph(g, a.output, PoseGraphFormat::kAuto, &warnings);
    for (const std::string& w : warnings) std::cerr << "slamkit: warning: " << w << "\n";
  }
  if (!a.trajectory.empty()) write_trajectory(a.trajectory, to_trajectory(g), TrajectoryFormat::kTum);
  if (!a.json.empty()) {
    nlohmann::json j = nlohmann::json::parse(r.summary.to_json());
    j["label"] = a.label.empty() ? a.input + " (" + a.solver + ", " + to_string(r.init.used) + ")" : a.label;
    j["file"] = a.input;
    j["format"] = g.format;
    j["dimension"] = g.dimension();
    j["vertices"] = g.vertices().size();
    j["edges"] = g.edges.size();
    j["init"] = to_string(r.init.used);
    j["init_requested"] = to_string(r.init.requested);
    j["initial_chi2"] = r.input_chi2;
    j["chi2_after_init"] = r.chi2_after_init;
    j["optimizer_initial_cost"] = r.summary.initial_cost;
    j["final_cost"] = r.summary.final_cost;
    j["final_chi2"] = r.final_chi2;
    j["robust"] = a.robust;
    j["time_load_s"] = load_time;
    j["time_init_s"] = r.init.time_s;
    j["time_ordering_s"] = r.time_ordering_s;
    j["time_optimize_s"] = r.summary.time_total_s;
    j["time_total_s"] = r.time_total_s;  // end to end: ordering + initialization + optimization
    j["time_end_to_end_s"] = r.time_total_s;
    j["notes"] = r.notes;
    write_json(a.json, j);
  }
  if (!r.summary.success())
    throw NumericalError("optimization failed: " + std::string(to_string(r.summary.termination)) + ": " +
                         r.summary.message);
}

}  // namespace

void add_optimize_command(CLI::App& app) {
  auto args = std::make_shared<OptimizeArgs>();
  CLI::App* cmd = app.add_subcommand("optimize", "Initialize and optimize a pose graph (g2o, TORO, GTSAM, or sim:NAME)");
  cmd->add_option("file", args->input, "Pose-graph file, or a built-in generated graph: sim:sphere, sim:manhattan")
      ->required();
  cmd->add_option("-o,--output", args->output, "Write the optimized graph (format from the extension)");
  cmd->add_option("--solver", args->solver, "gn | lm | tr-lm | dogleg | hogman")->capture_default_str();
  cmd->add_option("--init", args->init, "none | odometry | spanning-tree | linear | chordal | auto | sgd | toro | relax | mlr")
      ->capture_default_str();
  cmd->add_option("--max-iterations", args->max_iterations, "Iteration limit")->capture_default_str();
  cmd->add_option("--robust", args->robust, "Robust kernel on the edges, KERNEL:delta (huber, cauchy, tukey, "
                                            "geman-mcclure, dcs), e.g. cauchy:1");
  cmd->add_flag("--robust-loop-closures-only", args->robust_loops_only, "Apply --robust to loop closures only");
  cmd->add_option("--threads", args->threads, "Linearization threads (0: all cores)")->capture_default_str();
  cmd->add_option("--blas-threads", args->blas_threads,
                  "BLAS threads in the factorization (1 keeps results bit-identical; 0: = --threads)")
      ->capture_default_str();
  cmd->add_option("--function-tolerance", args->function_tolerance)->capture_default_str();
  cmd->add_option("--gradient-tolerance", args->gradient_tolerance)->capture_default_str();
  cmd->add_option("--parameter-tolerance", args->parameter_tolerance)->capture_default_str();
  cmd->add_option("--linear-solver", args->linear_solver, "auto | cholmod | eigen")->capture_default_str();
  cmd->add_option("--ordering", args->ordering, "auto | amd | metis | nesdis | natural")->capture_default_str();
  cmd->add_option("--format", args->format, "Input format: auto | g2o | toro | gtsam")->capture_default_str();
  cmd->add_flag("--repair-information", args->repair_information,
                "Project information matrices that are not positive definite to the PSD cone");
  cmd->add_flag("--allow-unknown-tags", args->allow_unknown_tags, "Skip unknown tags with a warning");
  cmd->add_option("--json", args->json, "Write the summary as JSON (- for stdout)");
  cmd->add_option("--trajectory", args->trajectory, "Write the optimized poses as a TUM trajectory");
  cmd->add_option("--config", args->config, "JSON file with any of the options above (flags win)");
  cmd->add_option("--label", args->label, "Name of this run in reports");
  cmd->add_flag("-q,--quiet", args->quiet, "No per-iteration progress");
  cmd->callback([cmd, args] { run(*cmd, *args); });
}

}  // namespace slamkit::cli
