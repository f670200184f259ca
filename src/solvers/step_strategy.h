// Internal: how each algorithm proposes a step and adapts its damping or radius.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "slamkit/linear/normal_equations.h"
#include "slamkit/linear/sparse_cholesky.h"
#include "slamkit/solvers/optimizer_options.h"

namespace slamkit::detail {

/// The current linear system and its solver, with timing of the linear algebra.
class LinearContext {
 public:
  LinearContext(NormalEquations& ne, SparseCholesky& chol) : ne_(ne), chol_(chol) {}
  NormalEquations& equations() { return ne_; }
  SparseCholesky& cholesky() { return chol_; }
  const Eigen::VectorXd& gradient() const { return ne_.gradient(); }
  int dim() const { return ne_.dim(); }

  /// Factorizes H with diag(H) + damping (or H itself when damping is null).
  bool factorize(const Eigen::VectorXd* damping);
  /// x = current_factor⁻¹ b.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  double inverse_factor_norm2(const Eigen::VectorXd& v);
  /// δᵀ H δ with the undamped H.
  double quadratic(const Eigen::VectorXd& d);
  /// Reduction of the Gauss-Newton model: −2gᵀδ − δᵀHδ. When δ solves the factorized system
  /// (H + Λ) δ = −g exactly (a direct solver, step not modified: see mark_step_solves_system),
  /// δᵀHδ = −gᵀδ − δᵀΛδ, so the reduction is −gᵀδ + δᵀΛδ without a product with H.
  double model_reduction(const Eigen::VectorXd& d);
  /// The step just computed is the solution of the factorized system (H + Λ) δ = −g.
  void mark_step_solves_system() { step_solves_system_ = direct_solves_; }
  /// Whether solve() is exact up to rounding (false for the iterative Schur path).
  void set_direct_solves(bool direct) { direct_solves_ = direct; }

  int solves = 0;          ///< factorizations since reset_counters()
  double time_s = 0.0;     ///< linear-algebra time since reset_counters()
  void reset_counters() { solves = 0, time_s = 0.0, step_solves_system_ = false; }

 private:
  NormalEquations& ne_;
  SparseCholesky& chol_;
  bool damped_ = false;
  bool direct_solves_ = false;
  bool step_solves_system_ = false;  // set per step by the strategy, cleared by reset_counters()
  Eigen::VectorXd work_;
};

class StepStrategy {
 public:
  virtual ~StepStrategy() = default;
  /// Proposes δ at the current linearization; false if no step can be computed.
  virtual bool compute_step(LinearContext& ctx, Eigen::VectorXd& step) = 0;
  virtual bool accept(double rho) const = 0;
  /// Adapts damping/radius after a step was accepted or rejected; false if the strategy
  /// cannot make progress any more (damping or radius at its limit).
  virtual bool update(double rho, bool accepted, const Eigen::VectorXd& step) = 0;
  /// The linearization changed (after an accepted step).
  virtual void new_linearization() {}
  /// λ or radius, for the progress report.
  virtual double damping() const = 0;
};

std::unique_ptr<StepStrategy> make_step_strategy(const OptimizerOptions& options);

}  // namespace slamkit::detail
