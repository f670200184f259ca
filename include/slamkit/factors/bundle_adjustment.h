// Bundle adjustment of a BalProblem: the factor graph (one BalCamera per camera, one Vector3
// per point, one BalReprojectionFactor per observation with unit noise) solved by the
// Optimizer with the points eliminated by the Schur complement (linear/schur_complement.h).
//
// Costs: the Optimizer's Summary reports Σ ρ(‖r‖²); BundleAdjustmentResult also gives
// ½ Σ ρ(‖r‖²), the convention of Ceres and the BAL literature.
// Gauge: BA is invariant to a similarity of the whole scene; as in Ceres' BAL solver no
// variable is fixed, and Levenberg-Marquardt damping handles the 7 free directions.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slamkit/core/bal_problem.h"
#include "slamkit/core/factor_graph.h"
#include "slamkit/core/values.h"
#include "slamkit/solvers/optimizer.h"

namespace slamkit {

inline Key bal_camera_key(int i) { return symbol('c', static_cast<std::uint64_t>(i)); }
inline Key bal_point_key(int j) { return symbol('p', static_cast<std::uint64_t>(j)); }
inline bool is_bal_point_key(Key k) { return symbol_char(k) == 'p'; }

struct BundleAdjustmentProblem {
  FactorGraph graph;
  Values values;
};

/// kernel (may be null) goes on every reprojection factor.
BundleAdjustmentProblem build_bundle_adjustment_problem(const BalProblem& p,
                                                        std::shared_ptr<const RobustKernel> kernel = nullptr);
/// Copies the optimized cameras and points back into p.
void copy_bundle_adjustment_estimates(const Values& values, BalProblem& p);

struct BundleAdjustmentOptions {
  OptimizerOptions optimizer = default_optimizer();
  std::shared_ptr<const RobustKernel> kernel;
  /// LM (the default) runs on BalNormalEquations (factors/bal_normal_equations.h: fixed-size
  /// kernels straight into the Schur solver's blocks); the other algorithms, or this flag, use
  /// the generic Optimizer on the factor graph.
  bool use_factor_graph = false;
  /// LM with Ceres' defaults (radius 1e4 ⇒ λ₀ = 1e-4 on diag(JᵀJ)) and its function tolerance
  /// 1e-6; points eliminated by the Schur complement, method chosen by size.
  static OptimizerOptions default_optimizer();
};

struct BundleAdjustmentResult {
  Summary summary;
  double initial_cost = 0.0, final_cost = 0.0;  ///< ½ Σ ρ(‖r‖²)
  double time_build_s = 0.0;                    ///< building the factor graph (or the solver's state)
  // summary.linear_solver names the reduced-system solver ("Schur complement (...) + dense LLT").
};

/// Optimizes p in place (cameras and points). Throws InputError for unusable input (see
/// validate_bal_geometry in io); numerical trouble is reported in the summary.
BundleAdjustmentResult optimize_bundle_adjustment(BalProblem& p, const BundleAdjustmentOptions& options = {});

}  // namespace slamkit
