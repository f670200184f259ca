// Options of the nonlinear least-squares Optimizer: one plain struct, every field with a
// default, all echoed in the Summary.
#pragma once

#include <functional>
#include <string>

#include "slamkit/core/key.h"
#include "slamkit/linear/schur_complement.h"
#include "slamkit/linear/sparse_cholesky.h"

namespace slamkit {

enum class Algorithm { kGaussNewton, kLevenbergMarquardt, kTrustRegionLM, kDogleg };
const char* to_string(Algorithm a);  ///< "gn", "lm", "tr-lm", "dogleg"
Algorithm parse_algorithm(const std::string& s);

struct IterationSummary;

struct OptimizerOptions {
  Algorithm algorithm = Algorithm::kLevenbergMarquardt;
  int max_iterations = 100;
  /// Stop when an accepted step changes the cost by less than this fraction of it (GTSAM's
  /// relativeErrorTol default; Ceres uses 1e-6, which costs one more iteration for no
  /// visible gain on the reference pose graphs, see docs/optimizer.md).
  double function_tolerance = 1e-5;
  /// Stop when max_i |g_i| falls below this (g = Jᵀr at the current estimate).
  double gradient_tolerance = 1e-10;
  /// Stop when ‖δ‖ ≤ parameter_tolerance · (‖x‖ + parameter_tolerance).
  double parameter_tolerance = 1e-8;

  // Gauss-Newton takes full steps even when they raise the cost (pose graphs often need one
  // such step); after gn_patience consecutive steps that do not improve on the best cost it
  // restarts from the best iterate with Levenberg-Marquardt. 0: pure Gauss-Newton.
  int gn_patience = 3;

  // Levenberg-Marquardt, (H + λ D) δ = −g with Nielsen's update of λ:
  // accept (ρ > 0): λ ← λ · max(1/3, 1 − (2ρ − 1)³), ν ← 2; reject: λ ← λ ν, ν ← 2ν.
  double lm_initial_lambda = 1e-5;   ///< relative: λ₀ = this · max(diag H) (D = I) or this (D = diag H)
  bool lm_diagonal_scaling = true;   ///< D = diag(H) (Marquardt) instead of I (Levenberg)
  double lm_max_lambda = 1e32;

  // Trust-region LM of the P3 paper: ‖D δ‖² ≤ μ with D² = diag(H) (Moré's scaling, kept as
  // the running maximum); ρ > increase_threshold ⇒ μ ← increase_factor · μ;
  // ρ < decrease_threshold ⇒ μ ← decrease_factor · μ; the step is accepted when ρ > accept_threshold.
  double tr_initial_radius = 1e4;
  double tr_increase_threshold = 0.75;
  double tr_decrease_threshold = 0.25;
  double tr_increase_factor = 2.0;
  double tr_decrease_factor = 0.5;
  double tr_accept_threshold = 1e-4;
  int tr_max_inner_solves = 4;  ///< factorizations per step to hit the radius (Moré-Hebden)
  double tr_min_radius = 1e-32;

  // Powell's dogleg in the Euclidean tangent norm.
  double dogleg_initial_radius = 1e4;
  double dogleg_accept_threshold = 1e-4;
  double dogleg_min_radius = 1e-32;

  // Linear algebra.
  SparseBackend linear_solver = SparseBackend::kAuto;
  OrderingMethod ordering = OrderingMethod::kAuto;
  int num_threads = 0;  ///< linearization threads; ≤ 0: all hardware threads
  /// BLAS threads inside the sparse factorization. 1 (default) keeps results bit-identical
  /// for any num_threads; multithreaded BLAS reorders floating-point sums. ≤ 0: num_threads.
  int blas_threads = 1;
  /// Elimination order over Values indices (variables not free are skipped); empty: computed
  /// from the problem with `ordering`.
  EliminationOrder variable_order;
  /// A symbolic analysis made for H's block pattern (e.g. by the initialization's systems over
  /// the same poses, InitSummary::symbolic): adopted when the pattern matches, else H is analyzed.
  SharedSymbolic shared_symbolic;
  /// Schur complement (linear/schur_complement.h): the variables for which this returns true
  /// (e.g. the landmarks of bundle adjustment) are eliminated first and the reduced system is
  /// solved with `schur`. Empty: the whole system goes to the sparse Cholesky.
  std::function<bool(Key)> schur_eliminate;
  SchurOptions schur;

  /// Called after every iteration (including rejected steps); return false to stop.
  std::function<bool(const IterationSummary&)> callback;
};

}  // namespace slamkit
