// slamkit optimize PROBLEM --format bal: bundle adjustment with the Schur complement.
#include "cmd_optimize_bal.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "slamkit/core/robust_kernel.h"
#include "slamkit/factors/bundle_adjustment.h"
#include "slamkit/io/bal_io.h"
#include "slamkit/sim/ba_generator.h"

namespace slamkit::cli {
namespace {

struct BaArgs {
  std::string linear = "auto", ply, preconditioner = "schur-jacobi";
  bool normalize = false;
  std::vector<double> perturb;  // rotation, translation, point sigmas
  std::uint64_t perturb_seed = 1;
  double pcg_tolerance = SchurOptions{}.pcg_tolerance;
};

BaArgs& ba_args() {
  static BaArgs a;
  return a;
}

}  // namespace

void add_bundle_adjustment_options(CLI::App* cmd) {
  BaArgs& a = ba_args();
  cmd->add_option("--linear", a.linear, "Bundle adjustment: auto | schur-dense | schur-cholesky | schur-pcg")
      ->capture_default_str();
  cmd->add_option("--preconditioner", a.preconditioner, "Bundle adjustment, schur-pcg: schur-jacobi | block-jacobi")
      ->capture_default_str();
  cmd->add_option("--pcg-tolerance", a.pcg_tolerance, "Bundle adjustment, schur-pcg: relative residual")
      ->capture_default_str();
  cmd->add_option("--ply", a.ply, "Bundle adjustment: write points and camera centres as PLY");
  cmd->add_flag("--normalize", a.normalize, "Bundle adjustment: centre and scale the scene first (cost unchanged)");
  cmd->add_option("--perturb", a.perturb, "Bundle adjustment: Gaussian noise on the start: ROT TRANS POINT sigmas")
      ->expected(3);
  cmd->add_option("--perturb-seed", a.perturb_seed, "Bundle adjustment: seed of --perturb")->capture_default_str();
}

bool is_bundle_adjustment_input(const std::string& input, const std::string& format) {
  if (format == "bal") return true;
  if (format != "auto") return false;
  return input.rfind("sim:ba", 0) == 0 || looks_like_bal_path(input);
}

void run_bundle_adjustment(const BundleAdjustmentCommonArgs& c) {
  const BaArgs& a = ba_args();
  check_outputs({{&a.ply, "--ply"}});  // -o and --json are checked by the caller
  BundleAdjustmentOptions o;
  OptimizerOptions& opt = o.optimizer;
  opt.algorithm = parse_algorithm(c.solver.empty() ? "lm" : c.solver);
  opt.max_iterations = c.max_iterations;
  opt.num_threads = c.threads;
  opt.blas_threads = c.blas_threads;
  opt.function_tolerance = c.function_tolerance;
  opt.gradient_tolerance = c.gradient_tolerance;
  opt.parameter_tolerance = c.parameter_tolerance;
  opt.schur.method = parse_schur_method(a.linear);
  if (a.preconditioner == "block-jacobi") opt.schur.preconditioner = SchurPreconditioner::kBlockJacobi;
  else if (a.preconditioner != "schur-jacobi")
    throw InputError("", 0, "preconditioner", "unknown preconditioner '" + a.preconditioner + "' (schur-jacobi, block-jacobi)");
  opt.schur.pcg_tolerance = a.pcg_tolerance;
  if (!c.robust.empty()) o.kernel = parse_robust_kernel(c.robust);

  const Stopwatch load_clock;
  BalReadReport report;
  BalProblem p;
  BaSimOptions sim;
  if (parse_ba_sim_spec(c.input, &sim)) {
    p = generate_ba_problem(sim);
  } else {
    p = read_bal(c.input, &report);
  }
  if (a.normalize) normalize_bal(p);
  if (!a.perturb.empty()) perturb_bal(p, {a.perturb[0], a.perturb[1], a.perturb[2], a.perturb_seed});
  validate_bal_geometry(p, &report);
  const double load_time = load_clock.seconds();
  for (const std::string& w : report.warnings) std::cerr << "slamkit: warning: " << w << "\n";

  if (!c.quiet) {
    std::printf("slamkit optimize %s: bundle adjustment, %d cameras, %d points, %d observations, loaded in %.4f s\n",
                c.input.c_str(), p.num_cameras(), p.num_points(), p.num_observations(), load_time);
    opt.callback = [&](const IterationSummary& it) {
      if (it.iteration == 0) std::printf("%s\n", Summary::progress_header().c_str());
      std::printf("%s\n", Summary::progress_line(it, opt.algorithm).c_str());
      std::fflush(stdout);
      return true;
    };
  }
  const BundleAdjustmentResult r = optimize_bundle_adjustment(p, o);
  std::printf("%s", r.summary.report().c_str());
  const double rms = std::sqrt(2.0 * r.final_cost / (2.0 * p.num_observations()));
  std::printf("  result           cost (1/2 sum r^2) %.10g -> %.10g, RMS reprojection error %.4g px, %.4f s (+ build %.4f s)\n",
              r.initial_cost, r.final_cost, rms, r.summary.time_total_s, r.time_build_s);

  if (!c.output.empty()) write_bal(c.output, p);
  if (!a.ply.empty()) write_bal_ply(a.ply, p);
  if (!c.json.empty()) {
    nlohmann::json j = nlohmann::json::parse(r.summary.to_json());
    j["label"] = c.label.empty() ? c.input + " (" + to_string(opt.algorithm) + ", " + a.linear + ")" : c.label;
    j["file"] = c.input;
    j["format"] = "bal";
    j["problem"] = "bundle_adjustment";
    j["cameras"] = p.num_cameras();
    j["points"] = p.num_points();
    j["observations"] = p.num_observations();
    j["linear"] = a.linear;
    j["initial_chi2"] = r.summary.initial_cost;
    j["final_chi2"] = r.summary.final_cost;
    j["initial_cost"] = r.initial_cost;  // ½ Σ ρ(‖r‖²), Ceres' convention
    j["final_cost"] = r.final_cost;
    j["rms_reprojection_error_px"] = rms;
    j["robust"] = c.robust;
    j["normalize"] = a.normalize;
    j["time_load_s"] = load_time;
    j["time_build_s"] = r.time_build_s;
    j["time_optimize_s"] = r.summary.time_total_s;
    j["time_total_s"] = r.summary.time_total_s + r.time_build_s;
    write_json(c.json, j);
  }
  if (!r.summary.success())
    throw NumericalError("optimization failed: " + std::string(to_string(r.summary.termination)) + ": " +
                         r.summary.message);
}

}  // namespace slamkit::cli
