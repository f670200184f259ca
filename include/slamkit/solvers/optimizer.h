// Optimizer: sparse nonlinear least squares on manifolds,
//     min_x Σ_f ρ_f(‖R_f r_f(x)‖²),   x ⊞ δ = x · Exp(δ) per variable,
// with Gauss-Newton, Levenberg-Marquardt (Nielsen's damping update), the trust-region LM of
// the P3 paper (radius μ on ‖Dδ‖²), or Powell's dogleg. Each iteration linearizes all factors
// (in parallel, deterministically), factorizes the normal equations with a sparse Cholesky
// whose ordering and symbolic analysis were computed once, and tests the step with the gain
// ratio ρ = (actual reduction) / (reduction predicted by the model −2gᵀδ − δᵀHδ).
// A step that makes the cost non-finite is rejected; a system that cannot be factorized is
// damped and retried, and if that fails the run ends with a clear termination message.
// An Optimizer holds only options; optimize() is reentrant for distinct Values.
#pragma once

#include "slamkit/core/factor_graph.h"
#include "slamkit/solvers/optimizer_options.h"
#include "slamkit/solvers/summary.h"

namespace slamkit {

class Optimizer {
 public:
  explicit Optimizer(OptimizerOptions options = {}) : options_(std::move(options)) {}
  const OptimizerOptions& options() const { return options_; }

  /// Optimizes `values` in place (fixed variables untouched). Throws InputError if the graph
  /// does not fit the values; numerical trouble is reported in the Summary, never thrown.
  Summary optimize(const FactorGraph& graph, Values& values) const;

 private:
  OptimizerOptions options_;
};

}  // namespace slamkit
