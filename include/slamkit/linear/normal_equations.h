// NormalEquations: the Gauss-Newton system of a FactorGraph around Values x,
//     H δ = −g,   H = Σ_f Ĵ_fᵀ Ĵ_f,   g = Σ_f Ĵ_fᵀ r̂_f,
// with Ĵ, r̂ the whitened, robustified Jacobians and residuals (Factor::linearize), and
// δ stacked over the free variables in elimination order: block k of H is the k-th free
// variable to eliminate (a fill-reducing order, postordered), so the sparse Cholesky
// factorizes H exactly as stored.
//
// The structure (which variables are free, their order, the block pattern of H, where each
// factor's JᵀJ blocks land in H's storage) is built once. linearize() then runs in two phases:
//   1. evaluate(): every factor is linearized into its own slot of a Jacobian buffer (parallel);
//   2. assemble(): every block column of H sums its contributions in factor order (parallel).
// No sum crosses threads, so H, g and the cost are bit-identical for any thread count.
// Variables that no factor touches are left out of the system (and unchanged).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/parallel.h"
#include "slamkit/linear/block_sparse_matrix.h"
#include "slamkit/linear/sparse_cholesky.h"

namespace slamkit {

class NormalEquations {
 public:
  /// Throws InputError if a factor uses a missing or mistyped variable, or no variable is free.
  /// variable_order (over Values indices; non-free variables are skipped) fixes the
  /// elimination order; otherwise `ordering` computes one.
  NormalEquations(const FactorGraph& graph, const Values& values, OrderingMethod ordering = OrderingMethod::kAuto,
                  const EliminationOrder* variable_order = nullptr);
  /// The fill-reducing ordering used ("AMD", "METIS", ... or the given order's name).
  const std::string& ordering() const { return ordering_; }

  int dim() const { return H_.rows(); }
  int num_free_variables() const { return H_.num_blocks(); }
  /// Values index of free variable k (block k of H).
  std::size_t free_variable(int k) const { return free_vars_[k]; }
  /// Block of H of the variable with this Values index, −1 if it is not free.
  int block_of_variable(std::size_t values_index) const { return block_of_var_[values_index]; }

  /// Fills H and g at x; returns the cost Σ ρ_f, or NaN if some factor is not finite.
  /// Same as evaluate(x) followed by assemble().
  double linearize(const Values& x, const ThreadPool& pool);
  /// Phase 1 alone: every factor's residual and Jacobians at x into the buffers; returns the
  /// cost (NaN if some factor is not finite). H and g keep their values, so an optimizer can
  /// evaluate a candidate and, if it rejects it, go on with the system at the current point;
  /// if it accepts it, assemble() completes the linearization at the candidate.
  double evaluate(const Values& x, const ThreadPool& pool);
  /// Phase 2 alone: H and g from the last evaluate() (which must have returned a finite cost).
  void assemble(const ThreadPool& pool);
  /// Index of the first factor whose cost was not finite in the last evaluate() (or linearize()).
  std::ptrdiff_t first_nonfinite_factor() const;

  BlockSparseMatrix& hessian() { return H_; }
  const BlockSparseMatrix& hessian() const { return H_; }
  const Eigen::VectorXd& gradient() const { return g_; }
  /// diag(H) as assembled by the last linearize() (before any damping).
  const Eigen::VectorXd& hessian_diagonal() const { return diag_; }
  /// H_ii ← diag_i + damping_i (damping of length dim()).
  void set_diagonal_damping(const Eigen::VectorXd& damping);
  /// Restores the undamped diagonal.
  void clear_damping();

  /// out ← x ⊞ δ on the free variables (out must be a copy of x's structure).
  void retract(const Values& x, const double* delta, Values& out, const ThreadPool& pool) const;

 private:
  struct FactorSlot {
    const Factor* factor;
    int residual_dim;
    std::size_t residual_offset;
    std::size_t first_var;  // into var_index_/var_jacobian_
  };
  struct Contribution {   // H(i, j) += J_aᵀ J_b, i ≥ j
    std::size_t ja, jb;   // offsets into jacobians_
    std::ptrdiff_t dest;  // offset into H values
    int rows, di, dj, ld;
    std::size_t residual;  // for diagonal contributions: g_j += J_bᵀ r (else unused)
    bool diagonal;
  };

  void linearize_factors(const Values& x, std::size_t begin, std::size_t end);
  void assemble_column(int j);

  const FactorGraph& graph_;
  std::vector<FactorSlot> slots_;
  std::vector<std::size_t> var_index_;         // per factor variable: Values index
  std::vector<std::ptrdiff_t> var_jacobian_;   // per factor variable: offset in jacobians_, −1 if fixed
  std::vector<std::size_t> free_vars_;         // block k → Values index
  std::vector<int> block_of_var_;              // Values index → block, −1 if not free
  std::vector<Contribution> contributions_;        // grouped by block column, factor order within
  std::vector<std::size_t> contribution_start_;    // block column j: [start[j], start[j + 1])
  std::vector<double> jacobians_, residuals_, factor_cost_;
  BlockSparseMatrix H_;
  Eigen::VectorXd g_, diag_;
  std::size_t max_arity_ = 0;
  bool evaluated_ = false;  // the buffers hold a finite evaluate() that assemble() may use
  std::string ordering_;
};

}  // namespace slamkit
