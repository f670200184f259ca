#include "slamkit/solvers/summary.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "string_format.h"

namespace slamkit {

const char* to_string(Termination t) {
  switch (t) {
    case Termination::kFunctionTolerance: return "function tolerance";
    case Termination::kGradientTolerance: return "gradient tolerance";
    case Termination::kParameterTolerance: return "parameter tolerance";
    case Termination::kMaxIterations: return "max iterations";
    case Termination::kTrustRegionLimit: return "damping/radius limit";
    case Termination::kLinearSolverFailure: return "linear solver failure";
    case Termination::kNonFiniteCost: return "non-finite cost";
    case Termination::kUserCallback: return "user callback";
  }
  return "?";
}

bool Summary::success() const {
  switch (termination) {
    case Termination::kFunctionTolerance:
    case Termination::kGradientTolerance:
    case Termination::kParameterTolerance:
    case Termination::kMaxIterations:
    case Termination::kUserCallback: return std::isfinite(final_cost);
    default: return false;
  }
}

namespace {
using detail::format;
const char* damping_label(Algorithm a) {
  switch (a) {
    case Algorithm::kGaussNewton: return "lambda";
    case Algorithm::kLevenbergMarquardt: return "lambda";
    case Algorithm::kTrustRegionLM: return "mu";
    case Algorithm::kDogleg: return "radius";
  }
  return "";
}
}  // namespace

std::string Summary::progress_header() {
  return format("%4s %16s %11s %10s %10s %9s %10s %4s %10s %10s", "iter", "cost", "cost_change", "|gradient|",
                "|step|", "rho", "damping", "lin", "t_lin[s]", "t_total[s]");
}

std::string Summary::progress_line(const IterationSummary& it, Algorithm) {
  const std::string gradient = std::isnan(it.gradient_norm) ? "-" : format("%.3e", it.gradient_norm);
  return format("%4d %16.9e %11.3e %10s %10.3e %9.2e %10.3e %4d %10.4f %10.4f%s", it.iteration, it.cost,
                it.cost_change, gradient.c_str(), it.step_norm, it.rho, it.damping, it.linear_solves,
                it.linear_solver_time_s, it.cumulative_time_s, it.accepted ? "" : "  (rejected)");
}

std::string Summary::report() const {
  std::ostringstream os;
  const char* algo = to_string(options.algorithm);
  os << "slamkit optimizer summary\n";
  os << format("  problem          %d variables (%d fixed), %d factors, %d residuals, tangent dim %d\n", num_variables,
               num_fixed, num_factors, num_residuals, tangent_dim);
  os << format("  solver           %s (%s: %s)\n", algo, damping_label(options.algorithm),
               options.algorithm == Algorithm::kGaussNewton ? "fallback only" : "adaptive");
  os << "  linear solver    " << linear_solver << ", ordering " << ordering
     << format(", factor nnz %.3g, %.3g flops\n", factor_nnz, factor_flops);
  if (linear_solver_is_fallback) os << "  WARNING          the fallback linear solver was used: expect slow solves\n";
  os << format("  threads          %d linearization (%s), %d BLAS (%s)\n", threads, thread_backend.c_str(),
               blas_threads, blas.c_str());
  if (!blas_better_core.empty())
    os << "  WARNING          OpenBLAS runs generic kernels on a CPU that supports " << blas_better_core
       << ": OPENBLAS_CORETYPE=" << blas_better_core << " factorizes about 2x faster\n";
  os << format("  cost (chi2)      initial %.10g -> final %.10g (%.3g%% of initial)\n", initial_cost, final_cost,
               initial_cost > 0 ? 100.0 * final_cost / initial_cost : 0.0);
  os << format("  iterations       %d (%d accepted), %d linear solves\n", iterations, accepted_steps, linear_solves);
  if (pcg_iterations > 0) os << format("  PCG              %ld conjugate-gradient iterations in all\n", pcg_iterations);
  if (fallback_iteration > 0)
    os << format("  fallback         Gauss-Newton made no progress for %d steps: continued with LM from the best "
                 "iterate at iteration %d\n",
                 options.gn_patience, fallback_iteration);
  os << format("  time             %.4f s total: setup %.4f, symbolic analysis %.4f, linearization %.4f, candidate evaluation %.4f, "
               "linear solves %.4f\n",
               time_total_s, time_setup_s, time_analyze_s, time_linearize_s, time_evaluate_s, time_linear_solver_s);
  os << "  termination      " << to_string(termination) << (message.empty() ? "" : ": " + message) << "\n";
  os << format("  tolerances       function %.1e, gradient %.1e, parameter %.1e, max iterations %d\n",
               options.function_tolerance, options.gradient_tolerance, options.parameter_tolerance,
               options.max_iterations);
  return os.str();
}

std::string Summary::to_json() const {
  nlohmann::json j;
  j["kind"] = "optimize";
  j["solver"] = to_string(options.algorithm);
  j["linear_solver"] = linear_solver;
  j["pcg_iterations"] = pcg_iterations;
  j["linear_solver_fallback"] = linear_solver_is_fallback;
  j["ordering"] = ordering;
  j["threads"] = threads;
  j["blas_threads"] = blas_threads;
  j["blas"] = blas;
  j["blas_better_core"] = blas_better_core;
  j["thread_backend"] = thread_backend;
  j["num_variables"] = num_variables;
  j["num_fixed"] = num_fixed;
  j["num_factors"] = num_factors;
  j["num_residuals"] = num_residuals;
  j["tangent_dim"] = tangent_dim;
  j["factor_nnz"] = factor_nnz;
  j["factor_flops"] = factor_flops;
  j["initial_chi2"] = initial_cost;
  j["final_chi2"] = final_cost;
  j["iterations"] = iterations;
  j["accepted_steps"] = accepted_steps;
  j["linear_solves"] = linear_solves;
  j["gn_fallback_iteration"] = fallback_iteration;
  j["termination"] = to_string(termination);
  j["message"] = message;
  j["success"] = success();
  j["time_total_s"] = time_total_s;
  j["time_setup_s"] = time_setup_s;
  j["time_analyze_s"] = time_analyze_s;
  j["time_linearize_s"] = time_linearize_s;
  j["time_evaluate_s"] = time_evaluate_s;
  j["time_linear_solver_s"] = time_linear_solver_s;
  j["options"] = {{"max_iterations", options.max_iterations},
                  {"gn_patience", options.gn_patience},
                  {"function_tolerance", options.function_tolerance},
                  {"gradient_tolerance", options.gradient_tolerance},
                  {"parameter_tolerance", options.parameter_tolerance},
                  {"lm_initial_lambda", options.lm_initial_lambda},
                  {"lm_diagonal_scaling", options.lm_diagonal_scaling},
                  {"tr_initial_radius", options.tr_initial_radius},
                  {"tr_increase_threshold", options.tr_increase_threshold},
                  {"tr_decrease_threshold", options.tr_decrease_threshold},
                  {"tr_increase_factor", options.tr_increase_factor},
                  {"tr_decrease_factor", options.tr_decrease_factor},
                  {"tr_accept_threshold", options.tr_accept_threshold},
                  {"tr_max_inner_solves", options.tr_max_inner_solves},
                  {"dogleg_initial_radius", options.dogleg_initial_radius},
                  {"linear_solver", to_string(options.linear_solver)},
                  {"ordering", to_string(options.ordering)},
                  {"num_threads", options.num_threads},
                  {"blas_threads", options.blas_threads}};
  nlohmann::json trace_json = nlohmann::json::array();
  for (const IterationSummary& it : trace) {
    trace_json.push_back({{"iteration", it.iteration},
                          {"cost", it.cost},
                          {"cost_change", it.cost_change},
                          {"gradient_norm", it.gradient_norm},
                          {"step_norm", it.step_norm},
                          {"rho", std::isfinite(it.rho) ? it.rho : -1e300},
                          {"damping", it.damping},
                          {"radius", it.damping},
                          {"linear_solves", it.linear_solves},
                          {"accepted", it.accepted},
                          {"linear_solver_time_s", it.linear_solver_time_s},
                          {"evaluate_time_s", it.evaluate_time_s},
                          {"assemble_time_s", it.assemble_time_s},
                          {"time_s", it.cumulative_time_s}});
  }
  j["trace"] = std::move(trace_json);
  return j.dump(2);
}

}  // namespace slamkit
