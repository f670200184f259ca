// Summary of an optimization: what was solved, how, what happened at every iteration, and
// why it stopped. report() is the full human-readable form, to_json() the machine form
// (keys as in the CLI's --json: initial_chi2, final_chi2, iterations, linear_solves, ...).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "slamkit/solvers/optimizer_options.h"

namespace slamkit {

enum class Termination {
  kFunctionTolerance,
  kGradientTolerance,
  kParameterTolerance,
  kMaxIterations,
  kTrustRegionLimit,     ///< damping too large / radius too small: no further progress possible
  kLinearSolverFailure,  ///< the system could not be factorized even with damping
  kNonFiniteCost,        ///< the initial cost is not finite
  kUserCallback,
};
const char* to_string(Termination t);

struct IterationSummary {
  int iteration = 0;
  double cost = 0.0;         ///< cost after this iteration (chi2 = Σ ρ(‖R r‖²))
  double cost_change = 0.0;  ///< previous cost − cost of the proposed step
  /// max |g_i| at the current estimate; NaN (JSON null, "-" in the progress line) when the
  /// run stopped before linearizing there (a tolerance met by the last accepted step).
  double gradient_norm = std::numeric_limits<double>::quiet_NaN();
  double step_norm = 0.0;      ///< ‖δ‖
  double rho = 0.0;            ///< actual / predicted reduction
  double damping = 0.0;        ///< LM λ, trust-region radius (TR-LM: μ; dogleg: Δ), 0 for GN
  int linear_solves = 0;       ///< factorizations in this iteration
  bool accepted = true;
  double linear_solver_time_s = 0.0;
  double evaluate_time_s = 0.0;  ///< residuals, Jacobians and cost of the candidate
  double assemble_time_s = 0.0;  ///< H and g at the accepted candidate
  double iteration_time_s = 0.0;
  double cumulative_time_s = 0.0;
};

struct Summary {
  OptimizerOptions options;
  std::string linear_solver;  ///< backend name, e.g. "CHOLMOD 3.0.14 supernodal"
  bool linear_solver_is_fallback = false;
  std::string ordering;       ///< the fill-reducing ordering actually used
  int threads = 1;       ///< linearization threads
  int blas_threads = 1;  ///< BLAS threads in the factorization
  std::string blas;      ///< the BLAS and its kernel set, e.g. "OpenBLAS SkylakeX"
  std::string blas_better_core;  ///< non-empty: OpenBLAS runs generic kernels; this set would be faster
  std::string thread_backend;

  int num_variables = 0, num_fixed = 0, num_factors = 0, num_residuals = 0, tangent_dim = 0;
  double factor_nnz = 0.0, factor_flops = 0.0;

  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;  ///< iterations performed (accepted + rejected steps)
  int accepted_steps = 0;
  int linear_solves = 0;
  long pcg_iterations = 0;     ///< conjugate-gradient iterations (Schur complement with PCG), 0 otherwise
  int fallback_iteration = 0;  ///< Gauss-Newton switched to LM at this iteration (0: never)
  Termination termination = Termination::kMaxIterations;
  std::string message;  ///< details on termination or failure
  bool success() const;  ///< converged (a tolerance reached) or hit max iterations with finite cost

  // time_linearize_s: the first linearization and the assembly of H, g at accepted points;
  // time_evaluate_s: evaluating candidates (cost, residuals and Jacobians; NormalEquations::evaluate).
  double time_total_s = 0.0, time_setup_s = 0.0, time_analyze_s = 0.0, time_linearize_s = 0.0,
         time_evaluate_s = 0.0, time_linear_solver_s = 0.0;
  std::vector<IterationSummary> trace;  ///< entry 0: the initial state

  std::string report() const;
  /// One line per iteration, as printed during the run.
  static std::string progress_header();
  static std::string progress_line(const IterationSummary& it, Algorithm a);
  std::string to_json() const;
};

}  // namespace slamkit
