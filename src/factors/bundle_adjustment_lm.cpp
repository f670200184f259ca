// Levenberg-Marquardt for BAL problems on BalNormalEquations + SchurComplementSolver. The loop
// is the Optimizer's (solvers/optimizer.cpp) specialised to LM: (H + λD) δ = −g with
// D = diag(H) clamped to [1e-6, 1e32], Nielsen's update (accept ρ > 0: λ ← λ·max(1/3, 1−(2ρ−1)³),
// ν ← 2; reject: λ ← λν, ν ← 2ν), the same tolerances, the same trace and Summary.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/linear/blas_runtime.h"
#include "slamkit/linear/schur_complement.h"

namespace slamkit {
namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Summary optimize_bal_levenberg_marquardt(const BalProblem& p, BalState& values, const OptimizerOptions& options,
                                         std::shared_ptr<const RobustKernel> kernel) {
  if (options.algorithm != Algorithm::kLevenbergMarquardt)
    throw std::invalid_argument("optimize_bal_levenberg_marquardt: options.algorithm must be lm");
  const double t_start = now_s();
  Summary s;
  s.options = options;
  const ThreadPool pool(options.num_threads);
  s.threads = pool.threads();
  s.thread_backend = ThreadPool::backend();
  BalNormalEquations ne(p, std::move(kernel), pool);
  s.num_variables = p.num_cameras() + p.num_points();
  s.num_factors = p.num_observations();
  s.num_residuals = 2 * p.num_observations();
  s.tangent_dim = ne.dim();
  s.blas_threads = options.blas_threads > 0 ? options.blas_threads : pool.threads();
  const BlasRuntime blas = blas_runtime();
  s.blas = blas.core.empty() ? blas.vendor : blas.vendor + " " + blas.core;
  s.blas_better_core = better_openblas_core();
  SchurOptions so = options.schur;
  so.blas_threads = s.blas_threads;
  SchurComplementSolver solver(ne.eliminate_flags(), pool, so);
  s.time_setup_s = now_s() - t_start;
  solver.analyze(ne.hessian());
  s.linear_solver = solver.name();
  s.ordering = "Schur (eliminated first)";
  s.time_analyze_s = solver.stats().analyze_time_s;
  s.factor_nnz = solver.stats().factor_nnz;
  s.factor_flops = solver.stats().factor_flops;

  BalState x = values, candidate = values;
  double t0 = now_s();
  double cost = ne.linearize(x);
  s.time_linearize_s += now_s() - t0;
  s.initial_cost = s.final_cost = cost;
  double lambda = options.lm_diagonal_scaling ? options.lm_initial_lambda
                                               : options.lm_initial_lambda * ne.hessian_diagonal().maxCoeff();
  double nu = 2.0;
  IterationSummary it0;
  it0.cost = cost;
  it0.gradient_norm = ne.gradient().lpNorm<Eigen::Infinity>();
  it0.damping = lambda;
  it0.cumulative_time_s = now_s() - t_start;
  s.trace.push_back(it0);
  if (options.callback) options.callback(it0);
  auto finish = [&](Termination t, std::string message) {
    s.termination = t;
    s.message = std::move(message);
  };

  if (!std::isfinite(cost)) {
    finish(Termination::kNonFiniteCost, "the initial cost is not finite (observation " +
                                            std::to_string(ne.first_nonfinite_observation(x)) + " does not evaluate)");
  } else if (it0.gradient_norm <= options.gradient_tolerance) {
    finish(Termination::kGradientTolerance, "the initial estimate is already a minimum (|g| <= tolerance)");
  } else {
    bool done = false;
    Eigen::VectorXd step(ne.dim()), rhs(ne.dim()), D;
    bool linearize_candidates = true;  // the last step was accepted
    for (int iter = 1; iter <= options.max_iterations && !done; ++iter) {
      const double t_iter = now_s();
      IterationSummary it;
      it.iteration = iter;
      // Step: factorize H + λD (more damping while it is not positive definite), solve.
      const double t_lin = now_s();
      int solves = 0;
      // In place (D keeps its allocation from one iteration to the next).
      if (options.lm_diagonal_scaling) D = ne.hessian_diagonal().cwiseMax(1e-6).cwiseMin(1e32);
      else D.setOnes(ne.dim());
      bool factored = false;
      rhs = -ne.gradient();
      while (true) {
        ne.set_diagonal_damping(lambda, D, false);  // the points' λD is added by the solver to C_j
        ++solves;
        if (solver.factorize(ne.hessian(), rhs.data(), ne.damping().data())) {  // the reduced rhs is formed with S
          factored = true;
          break;
        }
        lambda *= nu, nu *= 2.0;
        if (lambda > options.lm_max_lambda) break;
      }
      // After an accepted step the candidate is linearized right away (its cost comes with it, and
      // if it is accepted its H and g are the next iteration's: one pass over the observations per
      // iteration); a rejection then re-linearizes x. After a rejection (rejections come in runs)
      // the candidate's cost alone is evaluated. Either way H, g at x are the same bits. When it
      // is linearized, the points' back-substitution and retraction run inside its point pass
      // (retract_and_linearize: W_·j is read once, while in cache, then overwritten).
      const bool linearize_candidate = linearize_candidates;
      if (factored) {
        if (linearize_candidate) solver.solve_factored_kept(step.data());
        else solver.solve_factored_rhs(step.data());
      }
      it.linear_solves = solves;
      it.linear_solver_time_s = now_s() - t_lin;
      s.linear_solves += solves;
      s.time_linear_solver_s += it.linear_solver_time_s;
      auto linear_failure = [&] {
        finish(Termination::kLinearSolverFailure,
               "the normal equations could not be factorized even with large damping (rank-deficient problem?)");
      };
      const int nk = ne.dim() - 3 * ne.num_points();  // the cameras' rows (the points' come later if fused)
      if (!factored || !(linearize_candidate ? step.tail(nk) : step).allFinite()) {
        linear_failure();
        break;
      }
      t0 = now_s();
      double new_cost = 0.0;
      if (linearize_candidate) {
        new_cost = ne.retract_and_linearize(x, step.data(), candidate, [&](int j_begin, int j_end, double* d) {
          solver.back_substitute(j_begin, j_end, d);
        });
        it.assemble_time_s = now_s() - t0;
        s.time_linearize_s += it.assemble_time_s;
        if (!step.allFinite()) {
          linear_failure();
          break;
        }
      } else {
        ne.retract(x, step.data(), candidate);
        new_cost = ne.cost(candidate);
        it.evaluate_time_s = now_s() - t0;
        s.time_evaluate_s += it.evaluate_time_s;
      }
      // Model reduction −2gᵀδ − δᵀHδ. With the points back-substituted exactly,
      // δᵀ(H + λD)δ = −gᵀδ − δ_kᵀr_k (r_k = the reduced residual, 0 for a direct solve, CG's for
      // PCG), so −2gᵀδ − δᵀHδ = −gᵀδ + λδᵀDδ + δ_kᵀr_k: no pass over the blocks.
      // (rhs = −g at x: g itself may already be the candidate's; the same bits as −gᵀδ.)
      const double predicted = rhs.dot(step) + lambda * (D.array() * step.array().square()).sum() +
                               solver.last_residual_dot_solution();
      const double actual = cost - new_cost;
      double rho = predicted > 0.0 ? actual / predicted : (actual > 0.0 ? 1.0 : -1.0);
      if (!std::isfinite(new_cost)) rho = -std::numeric_limits<double>::infinity();
      const bool accepted = std::isfinite(new_cost) && rho > 0.0;
      if (accepted) {
        const double t = 2.0 * rho - 1.0;
        lambda *= std::max(1.0 / 3.0, 1.0 - t * t * t);
        nu = 2.0;
      } else {
        lambda *= nu;
        nu *= 2.0;
      }
      const bool can_continue = lambda <= options.lm_max_lambda;
      it.cost_change = actual;
      it.step_norm = step.norm();
      it.rho = rho;
      it.accepted = accepted;
      const double x_norm = BalNormalEquations::parameter_norm(x);
      const bool small_step = it.step_norm <= options.parameter_tolerance * (x_norm + options.parameter_tolerance);
      linearize_candidates = accepted;
      if (accepted) {
        std::swap(x, candidate);
        const double previous = cost;
        cost = new_cost;
        ++s.accepted_steps;
        if (std::abs(actual) <= options.function_tolerance * previous) {
          char buf[96];
          std::snprintf(buf, sizeof(buf), "relative cost change %.3e <= %.1e", std::abs(actual) / previous,
                        options.function_tolerance);
          finish(Termination::kFunctionTolerance, buf);
          done = true;
        } else if (small_step) {
          finish(Termination::kParameterTolerance, "step norm below parameter tolerance");
          done = true;
        } else {
          if (!linearize_candidate) {
            t0 = now_s();
            ne.linearize(x);
            it.assemble_time_s = now_s() - t0;
            s.time_linearize_s += it.assemble_time_s;
          }
          it.gradient_norm = ne.gradient().lpNorm<Eigen::Infinity>();
          if (it.gradient_norm <= options.gradient_tolerance) {
            finish(Termination::kGradientTolerance, "gradient max-norm below gradient tolerance");
            done = true;
          }
        }
      } else {
        if (linearize_candidate) {  // H and g back at x (cannot fail: they were formed there before)
          t0 = now_s();
          ne.linearize(x);
          const double t = now_s() - t0;
          it.assemble_time_s += t;
          s.time_linearize_s += t;
        }
        it.gradient_norm = s.trace.back().gradient_norm;
        if (!can_continue) {
          finish(Termination::kTrustRegionLimit, "damping/radius limit reached: no step decreases the cost");
          done = true;
        } else if (small_step) {
          finish(Termination::kParameterTolerance, "step norm below parameter tolerance");
          done = true;
        }
      }
      if (accepted && !done && !can_continue) {
        finish(Termination::kTrustRegionLimit, "damping/radius limit reached");
        done = true;
      }
      it.cost = cost;
      it.damping = lambda;
      it.iteration_time_s = now_s() - t_iter;
      it.cumulative_time_s = now_s() - t_start;
      s.trace.push_back(it);
      s.iterations = iter;
      if (options.callback && !options.callback(it) && !done) {
        finish(Termination::kUserCallback, "stopped by the callback");
        done = true;
      }
    }
    if (!done && s.termination == Termination::kMaxIterations)
      s.message = "reached max_iterations = " + std::to_string(options.max_iterations);
  }
  s.final_cost = cost;
  s.pcg_iterations = solver.total_pcg_iterations();
  values = std::move(x);
  s.time_total_s = now_s() - t_start;
  return s;
}

}  // namespace slamkit
