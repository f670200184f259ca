#include "slamkit/solvers/optimizer.h"

#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstdio>

#include "slamkit/core/error.h"
#include "slamkit/core/parallel.h"
#include "slamkit/linear/blas_runtime.h"
#include "step_strategy.h"

namespace slamkit {
namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double free_parameter_norm(const Values& x, const NormalEquations& ne) {
  double s = 0.0;
  for (int k = 0; k < ne.num_free_variables(); ++k) {
    const std::size_t i = ne.free_variable(k);
    const double* p = x.params(i);
    for (int a = 0; a < x.manifold(i).ambient_dim(); ++a) s += p[a] * p[a];
  }
  return std::sqrt(s);
}

}  // namespace

const char* to_string(Algorithm a) {
  switch (a) {
    case Algorithm::kGaussNewton: return "gn";
    case Algorithm::kLevenbergMarquardt: return "lm";
    case Algorithm::kTrustRegionLM: return "tr-lm";
    case Algorithm::kDogleg: return "dogleg";
  }
  return "?";
}

Algorithm parse_algorithm(const std::string& s) {
  for (auto a : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM, Algorithm::kDogleg})
    if (s == to_string(a)) return a;
  throw InputError("", 0, "solver", "unknown solver '" + s + "' (gn, lm, tr-lm, dogleg)");
}

Summary Optimizer::optimize(const FactorGraph& graph, Values& values) const {
  const double t_start = now_s();
  Summary s;
  s.options = options_;
  const ThreadPool pool(options_.num_threads);
  s.threads = pool.threads();
  s.thread_backend = ThreadPool::backend();

  // Schur complement: the eliminated variables first (then every one precedes its neighbours).
  EliminationOrder schur_order;
  const bool schur = static_cast<bool>(options_.schur_eliminate);
  if (schur && options_.variable_order.order.empty()) {
    schur_order.method = "Schur (eliminated first)";
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t i = 0; i < values.size(); ++i)
        if (options_.schur_eliminate(values.key(i)) == (pass == 0)) schur_order.order.push_back(static_cast<int>(i));
  }
  const EliminationOrder* order = !options_.variable_order.order.empty() ? &options_.variable_order
                                  : schur                                ? &schur_order
                                                                         : nullptr;
  NormalEquations ne(graph, values, options_.ordering, order);
  s.num_variables = static_cast<int>(values.size());
  s.num_fixed = static_cast<int>(values.num_fixed());
  s.num_factors = static_cast<int>(graph.size());
  for (const auto& f : graph) s.num_residuals += f->residual_dim();
  s.tangent_dim = ne.dim();

  s.blas_threads = options_.blas_threads > 0 ? options_.blas_threads : pool.threads();
  const BlasRuntime blas = blas_runtime();
  s.blas = blas.core.empty() ? blas.vendor : blas.vendor + " " + blas.core;
  s.blas_better_core = better_openblas_core();
  std::unique_ptr<SparseCholesky> chol;
  SchurComplementSolver* schur_solver = nullptr;
  if (schur) {
    std::vector<char> eliminate(ne.num_free_variables());
    for (int k = 0; k < ne.num_free_variables(); ++k)
      eliminate[k] = options_.schur_eliminate(values.key(ne.free_variable(k))) ? 1 : 0;
    SchurOptions so = options_.schur;
    so.blas_threads = s.blas_threads;
    auto solver = std::make_unique<SchurComplementSolver>(std::move(eliminate), pool, so);
    schur_solver = solver.get();
    chol = std::move(solver);
  } else {
    chol = make_sparse_cholesky(options_.linear_solver, options_.ordering, s.blas_threads);
  }
  s.linear_solver_is_fallback = chol->is_fallback();
  s.time_setup_s = now_s() - t_start;
  chol->analyze_sharing(ne.hessian(), options_.shared_symbolic);  // H is stored in elimination order
  s.linear_solver = chol->name();  // after analysis: says supernodal or simplicial
  s.ordering = ne.ordering();
  s.time_analyze_s = chol->stats().analyze_time_s;
  s.factor_nnz = chol->stats().factor_nnz;
  s.factor_flops = chol->stats().factor_flops;

  detail::LinearContext ctx(ne, *chol);
  ctx.set_direct_solves(!schur);  // the Schur path may solve iteratively (PCG)
  auto strategy = detail::make_step_strategy(options_);
  // The iterate lives in `values` itself (optimized in place; the NormalEquations keep no
  // reference to it), the candidate in one copy: a Values copy duplicates its key index.
  Values& x = values;
  Values candidate = values;
  // Best iterate so far: Gauss-Newton may pass through worse points; it never ends on one.
  // Kept as the flat parameter array (Values stores all parameters contiguously from
  // params(0)): no copy of the key index per improving step.
  const bool safeguard = options_.algorithm == Algorithm::kGaussNewton && options_.gn_patience > 0;
  std::vector<double> best = values.parameter_data();
  auto restore_best = [&best](Values& into) { std::copy(best.begin(), best.end(), into.params(0)); };
  int non_improving = 0;
  OptimizerOptions fallback_options;

  double t0 = now_s();
  double cost = ne.linearize(x, pool);
  s.time_linearize_s += now_s() - t0;
  s.initial_cost = s.final_cost = cost;
  double best_cost = cost;
  IterationSummary it0;
  it0.cost = cost;
  it0.gradient_norm = ne.gradient().lpNorm<Eigen::Infinity>();
  it0.damping = strategy->damping();
  it0.cumulative_time_s = now_s() - t_start;
  s.trace.push_back(it0);
  if (options_.callback) options_.callback(it0);

  auto finish = [&](Termination t, std::string message) {
    s.termination = t;
    s.message = std::move(message);
  };

  if (!std::isfinite(cost)) {
    finish(Termination::kNonFiniteCost, "the initial cost is not finite (factor " +
                                            std::to_string(ne.first_nonfinite_factor()) + " does not evaluate)");
  } else if (it0.gradient_norm <= options_.gradient_tolerance) {
    finish(Termination::kGradientTolerance, "the initial estimate is already a minimum (|g| <= tolerance)");
  } else {
    bool done = false;
    Eigen::VectorXd step;
    for (int iter = 1; iter <= options_.max_iterations && !done; ++iter) {
      const double t_iter = now_s();
      IterationSummary it;
      it.iteration = iter;
      ctx.reset_counters();
      if (!strategy->compute_step(ctx, step)) {
        s.linear_solves += ctx.solves;
        s.time_linear_solver_s += ctx.time_s;
        finish(Termination::kLinearSolverFailure,
               "the normal equations could not be factorized even with large damping (rank-deficient problem?)");
        break;
      }
      const double predicted = ctx.model_reduction(step);
      ne.retract(x, step.data(), candidate, pool);
      // The candidate's residuals and Jacobians (phase 1 of its linearization): gives its cost,
      // leaves H and g at x for a rejected step, and is assembled if the step is accepted.
      t0 = now_s();
      const double new_cost = ne.evaluate(candidate, pool);
      it.evaluate_time_s = now_s() - t0;
      s.time_evaluate_s += it.evaluate_time_s;
      const double actual = cost - new_cost;
      double rho = predicted > 0.0 ? actual / predicted : (actual > 0.0 ? 1.0 : -1.0);
      if (!std::isfinite(new_cost)) rho = -std::numeric_limits<double>::infinity();
      const bool accepted = std::isfinite(new_cost) && strategy->accept(rho);
      const bool can_continue = strategy->update(rho, accepted, step);

      it.cost_change = actual;
      it.step_norm = step.norm();
      it.rho = rho;
      it.accepted = accepted;
      it.linear_solves = ctx.solves;
      it.linear_solver_time_s = ctx.time_s;
      s.linear_solves += ctx.solves;
      s.time_linear_solver_s += ctx.time_s;
      const double x_norm = free_parameter_norm(x, ne);
      const bool small_step = it.step_norm <= options_.parameter_tolerance * (x_norm + options_.parameter_tolerance);

      if (accepted) {
        std::swap(x, candidate);
        const double previous = cost;
        cost = new_cost;
        ++s.accepted_steps;
        if (cost < best_cost) {
          best_cost = cost;
          best = x.parameter_data();
          non_improving = 0;
        } else {
          ++non_improving;
        }
        if (safeguard && s.fallback_iteration == 0 && non_improving >= options_.gn_patience) {
          // Gauss-Newton is not converging: continue from the best iterate with LM.
          restore_best(x);
          cost = best_cost;
          s.fallback_iteration = iter;
          fallback_options = options_;
          fallback_options.algorithm = Algorithm::kLevenbergMarquardt;
          strategy = detail::make_step_strategy(fallback_options);  // keeps a reference to it
          t0 = now_s();
          cost = ne.linearize(x, pool);
          s.time_linearize_s += now_s() - t0;
          it.gradient_norm = ne.gradient().lpNorm<Eigen::Infinity>();
        } else if (std::abs(actual) <= options_.function_tolerance * previous) {
          char buf[96];
          std::snprintf(buf, sizeof(buf), "relative cost change %.3e <= %.1e", std::abs(actual) / previous,
                        options_.function_tolerance);
          finish(Termination::kFunctionTolerance, buf);
          done = true;
        } else if (small_step) {
          finish(Termination::kParameterTolerance, "step norm below parameter tolerance");
          done = true;
        } else {
          t0 = now_s();
          ne.assemble(pool);  // x is the candidate evaluated above
          it.assemble_time_s = now_s() - t0;
          s.time_linearize_s += it.assemble_time_s;
          strategy->new_linearization();
          it.gradient_norm = ne.gradient().lpNorm<Eigen::Infinity>();
          if (it.gradient_norm <= options_.gradient_tolerance) {
            finish(Termination::kGradientTolerance, "gradient max-norm below gradient tolerance");
            done = true;
          }
        }
      } else {
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
      it.damping = strategy->damping();
      it.iteration_time_s = now_s() - t_iter;
      it.cumulative_time_s = now_s() - t_start;
      s.trace.push_back(it);
      s.iterations = iter;
      if (options_.callback && !options_.callback(it) && !done) {
        finish(Termination::kUserCallback, "stopped by the callback");
        done = true;
      }
    }
    if (!done && s.termination == Termination::kMaxIterations)
      s.message = "reached max_iterations = " + std::to_string(options_.max_iterations);
  }
  if (best_cost < cost) {  // only Gauss-Newton can end above its best iterate
    restore_best(x);
    cost = best_cost;
    s.message += "; returned the best iterate seen";
  }
  s.final_cost = cost;
  if (schur_solver) s.pcg_iterations = schur_solver->total_pcg_iterations();
  s.time_total_s = now_s() - t_start;
  return s;
}

}  // namespace slamkit
