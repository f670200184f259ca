// slamkit optimize FILE: initialize and optimize a pose graph, print progress and a summary.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "calibration_cli.h"
#include "cli_util.h"
#include "cmd_optimize_bal.h"
#include "commands.h"
#include "optimize_config.h"
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
  OptimizeSettings s;  // what --config can set too (optimize_config.h)
  bool allow_unknown_tags = false, quiet = false;
};

PoseGraph load(const OptimizeArgs& a, PoseGraphReadReport* report) {
  PoseGraphReadOptions ro;
  ro.format = parse_pose_graph_format(a.s.format);
  ro.repair_information = a.s.repair_information;
  ro.unknown_tags_as_warnings = a.allow_unknown_tags;
  return load_pose_graph(a.input, ro, report);
}

void run(const CLI::App& cmd, OptimizeArgs a) {
  check_outputs({{&a.output, "--output"}, {&a.json, "--json"}, {&a.trajectory, "--trajectory"}});
  if (!a.config.empty()) read_optimize_config(a.config, a.s, [&cmd](const char* flag) { return cmd.count(flag) > 0; });
  validate(a.s, "command line");  // flags too: names parse, counts and tolerances in their domain
  if (is_bundle_adjustment_input(a.input, a.s.format)) {  // BAL files, sim:ba (cmd_optimize_bal.cpp)
    BundleAdjustmentCommonArgs b{a.input, a.output, a.json, a.s.robust, a.label, cmd.count("--solver") ? a.s.solver : ""};
    b.max_iterations = a.s.max_iterations, b.threads = a.s.threads, b.blas_threads = a.s.blas_threads, b.quiet = a.quiet;
    if (cmd.count("--function-tolerance")) b.function_tolerance = a.s.function_tolerance;
    b.gradient_tolerance = a.s.gradient_tolerance, b.parameter_tolerance = a.s.parameter_tolerance;
    return run_bundle_adjustment(b);
  }
  if (a.s.solver == "hogman") {  // the hierarchical back end (optimize_hogman.cpp)
    PoseGraph g = load(a, nullptr);
    return run_hogman_optimize(g, {a.input, a.json, a.output, a.trajectory, a.label, a.quiet, a.s.threads > 0 ? a.s.threads : 1});
  }
  if (!a.output.empty() && format_from_extension(a.output) == PoseGraphFormat::kAuto)
    throw InputError(a.output, 0, "--output", "cannot tell the output format from the extension (use .g2o, .graph or .txt)");
  PoseGraphOptimizerOptions o;
  o.init = parse_init_method(a.s.init);
  o.keep_estimates_chi2_per_dof = a.s.keep_estimates_chi2_per_dof;
  o.optimizer.algorithm = parse_algorithm(a.s.solver);
  o.optimizer.max_iterations = a.s.max_iterations;
  o.optimizer.num_threads = a.s.threads;
  o.optimizer.blas_threads = a.s.blas_threads;
  o.optimizer.function_tolerance = a.s.function_tolerance;
  o.optimizer.gradient_tolerance = a.s.gradient_tolerance;
  o.optimizer.parameter_tolerance = a.s.parameter_tolerance;
  o.optimizer.linear_solver = parse_sparse_backend(a.s.linear_solver);
  o.optimizer.ordering = parse_ordering(a.s.ordering);
  if (!a.s.robust.empty()) o.problem.kernel = parse_robust_kernel(a.s.robust);
  o.problem.kernel_on_odometry = !a.s.robust_loop_closures_only;
  o.problem.calibration = parse_calibrate_option(a.s.calibrate);

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
  print_calibration(r.calibration);

  if (!a.output.empty()) {
    std::vector<std::string> warnings;
    write_pose_graph(g, a.output, PoseGraphFormat::kAuto, &warnings);
    for (const std::string& w : warnings) std::cerr << "slamkit: warning: " << w << "\n";
  }
  if (!a.trajectory.empty()) write_trajectory(a.trajectory, to_trajectory(g), TrajectoryFormat::kTum);
  if (!a.json.empty()) {
    nlohmann::json j = nlohmann::json::parse(pose_graph_result_to_json(r, g));
    j["label"] = a.label.empty() ? a.input + " (" + a.s.solver + ", " + to_string(r.init.used) + ")" : a.label;
    j["file"] = a.input;
    j["robust"] = a.s.robust;
    j["config"] = nlohmann::json::parse(optimize_config_to_json(a.s));  // the run's settings, reusable as --config
    j["time_load_s"] = load_time;
    if (j.contains("calibration")) add_calibration_truth_json(j, a.input);
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
  cmd->add_option("--solver", args->s.solver, "gn | lm | tr-lm | dogleg | hogman")->capture_default_str();
  cmd->add_option("--init", args->s.init, "none | odometry | spanning-tree | linear | chordal | auto | sgd | toro | relax | mlr")
      ->capture_default_str();
  cmd->add_option("--keep-estimates-chi2-per-dof", args->s.keep_estimates_chi2_per_dof,
                  "--init auto starts from the graph's estimates when their chi2 <= this x degrees of freedom (0: never)")
      ->capture_default_str();
  cmd->add_option("--max-iterations", args->s.max_iterations, "Iteration limit")->capture_default_str();
  cmd->add_option("--robust", args->s.robust, "Robust kernel on the edges, KERNEL:delta (huber, cauchy, tukey, "
                                            "geman-mcclure, dcs), e.g. cauchy:1");
  cmd->add_flag("--robust-loop-closures-only", args->s.robust_loop_closures_only, "Apply --robust to loop closures only");
  cmd->add_option("--threads", args->s.threads, "Linearization threads (0: all cores)")->capture_default_str();
  cmd->add_option("--blas-threads", args->s.blas_threads,
                  "BLAS threads in the factorization (1 keeps results bit-identical; 0: = --threads)")
      ->capture_default_str();
  cmd->add_option("--function-tolerance", args->s.function_tolerance)->capture_default_str();
  cmd->add_option("--gradient-tolerance", args->s.gradient_tolerance)->capture_default_str();
  cmd->add_option("--parameter-tolerance", args->s.parameter_tolerance)->capture_default_str();
  cmd->add_option("--linear-solver", args->s.linear_solver, "auto | cholmod | eigen")->capture_default_str();
  cmd->add_option("--ordering", args->s.ordering, "auto | amd | metis | nesdis | natural")->capture_default_str();
  cmd->add_option("--format", args->s.format, "Input format: auto | g2o | toro | gtsam | bal")->capture_default_str();
  cmd->add_flag("--repair-information", args->s.repair_information,
                "Project information matrices that are not positive definite to the PSD cone");
  cmd->add_flag("--allow-unknown-tags", args->allow_unknown_tags, "Skip unknown tags with a warning");
  cmd->add_option("--calibrate", args->s.calibrate,
                  "Calibration variables to estimate: auto | none | offset,odometry (docs/calibration.md)")
      ->capture_default_str();
  cmd->add_option("--json", args->json, "Write the summary as JSON (- for stdout)");
  cmd->add_option("--trajectory", args->trajectory, "Write the optimized poses as a TUM trajectory");
  cmd->add_option("--config", args->config, "JSON file with any of the options above (flags win)");
  cmd->add_option("--label", args->label, "Name of this run in reports");
  cmd->add_flag("-q,--quiet", args->quiet, "No per-iteration progress");
  add_bundle_adjustment_options(cmd);
  cmd->callback([cmd, args] { run(*cmd, *args); });
}

}  // namespace slamkit::cli
