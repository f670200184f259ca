// BalNormalEquations: the normal equations H δ = −g of bundle adjustment, built directly from
// the observations with fixed-size kernels (bal_reprojection) — no factor graph, no generic
// assembly, no Jacobians kept beyond the few numbers the camera reduction needs.
//
// Tangent order: points first (3 each), then cameras (9 each), as the Optimizer orders a Schur
// problem. With F_ij = ∂r_ij/∂camera_i (2×9) and E_ij = ∂r_ij/∂X_j (2×3), after the robust
// kernel's correction (Triggs, exactly as Factor::linearize), H holds only the λ-independent
// pieces the Schur complement needs:
//   C_j = Σ_i E_ijᵀE_ij (3×3 per point),  W_ij = F_ijᵀE_ij (9×3 per observed pair),
//   B_i = Σ_j F_ijᵀF_ij (9×9 per camera; cameras never share a block),
// g = Jᵀr, laid out as a BlockSparseMatrix (point columns [C_j; W_·j], camera columns [B_i]) so
// that SchurComplementSolver forms S = B − Σ_j W_·j C_j⁻¹ W_·jᵀ (or applies it, PCG) from them
// for every λ without re-evaluating anything.
// Parallelism: one pass over points (r, E, F of its observations in camera order; writes C_j,
// g_j and W_ij into the point's column of H, in order), one over cameras (the fused kernel again
// on four observations of the camera at a time, one per SIMD lane, for B_i and g_i: recomputing
// F costs less than storing it, 144 B per observation written in camera order and read back).
// Nothing is kept per observation beyond W. Costs are summed per fixed chunk of points, then
// chunk by chunk, B_i per lane then lane by lane: bit-identical for any thread count.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "slamkit/core/bal_problem.h"
#include "slamkit/core/parallel.h"
#include "slamkit/core/robust_kernel.h"
#include "slamkit/factors/bal_reprojection_factor.h"
#include "slamkit/linear/block_sparse_matrix.h"
#include "slamkit/solvers/summary.h"

namespace slamkit {

/// The variables of a BAL problem as the solver moves them (cameras on SO3 × R⁶).
struct BalState {
  std::vector<BalCamera> cameras;
  std::vector<Eigen::Vector3d> points;
};
BalState make_bal_state(const BalProblem& p);
void copy_bal_state(const BalState& x, BalProblem& p);

/// An observation as the point pass reads it (in point order, then camera order).
struct BalPointObservation {
  std::ptrdiff_t w_off;  // offset of W_ij in H's values
  int camera, point;
  double z[2];
};
/// An observation as the camera pass reads it (in camera order, then point order).
struct BalCameraObservation {
  int point;
  double z[2];
};

/// The point pass runs on eight lanes where the CPU has AVX-512 and on four elsewhere, with the
/// same bits; false forces four lanes (for tests that compare the two; not for concurrent use).
void bal_point_pass_allow_eight_lanes(bool allow);

class BalNormalEquations {
 public:
  /// kernel may be null (squared loss). The problem and the pool must outlive this object.
  BalNormalEquations(const BalProblem& p, std::shared_ptr<const RobustKernel> kernel, const ThreadPool& pool);

  int dim() const { return hessian_.rows(); }
  int num_points() const { return np_; }
  int num_cameras() const { return nc_; }
  /// Block b of H is a point (the blocks SchurComplementSolver eliminates).
  std::vector<char> eliminate_flags() const;

  /// Σ ρ(‖r‖²) at x, without Jacobians (NaN/inf if some residual is not finite).
  double cost(const BalState& x) const;
  /// H, g and diag(H) at x (undamped); returns the cost at x.
  double linearize(const BalState& x);
  /// retract(x, δ, out) then linearize(out) in one pass over the points: δ's camera rows are
  /// given; for each chunk of points [j_begin, j_end), back_substitute(j_begin, j_end, δ) first
  /// writes their rows of δ (it may read H's columns of those points: they are overwritten only
  /// after it returns; SchurComplementSolver::back_substitute), then the points are retracted and
  /// their observations linearized at out while their W blocks are still in cache. The same bits
  /// as the three steps apart; returns the cost at out.
  double retract_and_linearize(const BalState& x, double* step, BalState& out,
                               const std::function<void(int, int, double*)>& back_substitute);
  /// Index of the first observation whose residual is not finite at x (−1 if none).
  int first_nonfinite_observation(const BalState& x) const;

  const BlockSparseMatrix& hessian() const { return hessian_; }
  const Eigen::VectorXd& gradient() const { return g_; }
  const Eigen::VectorXd& hessian_diagonal() const { return diag_; }
  /// diag(H) ← diag + damping (replaces any previous damping); clear_damping restores it.
  void set_diagonal_damping(const Eigen::VectorXd& damping);
  /// The same with damping = λ·D, formed element by element (no temporary vector; same bits).
  /// points_in_h = false: only the camera blocks' diagonals are damped in H; the points' damping
  /// is left in damping() for SchurComplementSolver::factorize(H, b, damping().data()) to add
  /// to C_j as it inverts it (no pass over H's point columns, which are not in cache by then).
  void set_diagonal_damping(double lambda, const Eigen::VectorXd& D, bool points_in_h = true);
  /// The damping of the last set_diagonal_damping (λ·D or the vector given), H's row order.
  const Eigen::VectorXd& damping() const { return damping_; }
  void clear_damping();
  /// δᵀ H δ with the undamped H.
  double quadratic(const Eigen::VectorXd& d) const;
  /// out = x ⊞ δ (points additive, cameras by BalCamera::plus).
  void retract(const BalState& x, const double* step, BalState& out) const;
  /// ‖x‖ over the ambient parameters (quaternion, t, f, k1, k2, points), for the parameter tolerance.
  static double parameter_norm(const BalState& x);

 private:
  template <bool kJacobians>
  double point_pass(const BalState& x, std::vector<double>* chunk_cost,
                    const std::function<void(int, int)>* before_chunk = nullptr);
  void linearize_camera_blocks(const BalState& x);
  void retract_cameras(const BalState& x, const double* step, BalState& out) const;
  void camera_frames(const BalState& x) const;
  using PointObs = BalPointObservation;

  const BalProblem& p_;
  std::shared_ptr<const RobustKernel> kernel_;
  const ThreadPool& pool_;
  int np_ = 0, nc_ = 0;
  std::vector<int> pt_ptr_;             // observations of point j: pt_obs_[pt_ptr_[j] .. pt_ptr_[j+1]), camera order
  std::vector<PointObs> pt_obs_;
  std::vector<std::ptrdiff_t> c_off_;    // offset of C_j in H's values
  std::vector<int> cam_ptr_;            // observations of camera i: slots [cam_ptr_[i], cam_ptr_[i+1]), point order
  BlockSparseMatrix hessian_;
  Eigen::VectorXd g_, diag_, damping_;
  bool damped_ = false;
  int damped_from_ = 0;  // rows [damped_from_, dim) carry their damping in H
  std::vector<BalCameraObservation> cam_obs_;  // camera order (slot order)
  mutable std::vector<BalCameraFrame> frames_;
  mutable std::vector<double> chunk_cost_;
};

/// Levenberg-Marquardt on a BAL problem with BalNormalEquations and SchurComplementSolver
/// (points eliminated): the Optimizer's LM (Nielsen's λ update, D = clamped diag(H), the same
/// tolerances, trace, callback and Summary) without its generic factor-graph machinery.
/// After an accepted step the candidate is linearized at once (its cost with it; accepted, that is
/// the next iteration's H; rejected, x is linearized again); after a rejection candidates are
/// evaluated without Jacobians. H, g at every accepted point are the same bits either way.
/// options.algorithm must be kLevenbergMarquardt. x is updated in place.
Summary optimize_bal_levenberg_marquardt(const BalProblem& p, BalState& x, const OptimizerOptions& options,
                                         std::shared_ptr<const RobustKernel> kernel = nullptr);

}  // namespace slamkit
