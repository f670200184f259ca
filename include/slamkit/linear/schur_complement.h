// SchurComplementSolver: solves H x = b by eliminating a class of variables first (landmarks
// in bundle adjustment, inverse depths in a visual-inertial window), as a SparseCholesky so
// that every step strategy of the Optimizer (GN, LM, TR-LM, dogleg) runs on top of it.
//
// With the blocks of H split into eliminated (e) and kept (k) ones,
//     H = [ C  Eᵀ ]   C block diagonal (no two eliminated blocks share a factor),
//         [ E  B  ]
// the reduced system is S x_k = b_k − E C⁻¹ b_e with S = B − E C⁻¹ Eᵀ, then back-substitution
// x_e = C⁻¹ (b_e − Eᵀ x_k). S is solved
//   kDense     explicitly, as a dense matrix with a dense Cholesky (a few hundred kept blocks);
//   kCholesky  explicitly, as a block-sparse matrix with CHOLMOD (ordering computed once);
//   kPcg       implicitly: conjugate gradients with S v = B v − E (C⁻¹ (Eᵀ v)) (S never formed),
//              preconditioned by the block diagonal of S (Schur-Jacobi) or of B (block-Jacobi);
//   kAuto      by size (see choose_schur_method).
// Requirements (checked by analyze, std::invalid_argument otherwise): no two eliminated blocks
// are adjacent, and every eliminated block comes before all its neighbours in H's block order
// (true for any order that eliminates them first, postordered or not).
// Every phase runs on the ThreadPool over eliminated or kept blocks with fixed per-block
// summation order, so results are bit-identical for any thread count (CHOLMOD with 1 BLAS
// thread). inverse_factor_norm2(v) = vᵀ H⁻¹ v (the squared norm of L⁻¹ v for H = L Lᵀ), by a solve.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/core/parallel.h"
#include "slamkit/linear/sparse_cholesky.h"

namespace slamkit {

enum class SchurMethod { kAuto, kDense, kCholesky, kPcg };
enum class SchurPreconditioner { kSchurJacobi, kBlockJacobi };
const char* to_string(SchurMethod m);  ///< "auto", "schur-dense", "schur-cholesky", "schur-pcg"
/// The names above (also "dense", "cholesky", "pcg"); throws InputError otherwise.
SchurMethod parse_schur_method(const std::string& s);

struct SchurOptions {
  SchurMethod method = SchurMethod::kAuto;
  SchurPreconditioner preconditioner = SchurPreconditioner::kSchurJacobi;
  /// PCG (x₀ = 0) stops at the first of: ‖r_i‖ ≤ pcg_tolerance · ‖r₀‖; the truncated-Newton
  /// test of Nash and Sofer on the quadratic model Q(x) = ½xᵀSx − bᵀx,
  /// i · (Q_i − Q_{i−1}) / Q_i < pcg_q_tolerance (the model's last decrease is a small share of
  /// its average decrease per iteration; 0 disables it); pcg_max_iterations. The residual test
  /// alone needed ~90 CG iterations per LM step on sim:ba 200 (the residual of a badly
  /// conditioned S falls slowly long after Q has stopped improving); see docs/bundle_adjustment.md.
  double pcg_tolerance = 1e-6;
  double pcg_q_tolerance = 0.1;
  int pcg_max_iterations = 500;
  /// kAuto: dense when the reduced system has at most this many rows.
  int auto_dense_max_dim = 1200;
  /// kAuto: PCG instead of CHOLMOD when the factor of S would need more flops than this.
  double auto_pcg_min_flops = 2e10;
  OrderingMethod ordering = OrderingMethod::kAuto;  ///< for kCholesky
  int blas_threads = 1;
};

class SchurComplementSolver final : public SparseCholesky {
 public:
  /// eliminate[b] != 0: block b of H is eliminated. The pool must outlive the solver.
  SchurComplementSolver(std::vector<char> eliminate, const ThreadPool& pool, SchurOptions options = {});
  ~SchurComplementSolver() override;

  std::string name() const override;
  bool is_fallback() const override { return false; }
  void analyze(const BlockSparseMatrix& A, const EliminationOrder* block_order = nullptr) override;
  bool factorize(const BlockSparseMatrix& A) override;
  /// factorize(A) that also forms the reduced right-hand side b_k − E C⁻¹ b_e of this b while
  /// S (or the Schur-Jacobi preconditioner) is formed, where E C⁻¹ is at hand: no separate pass
  /// over the E blocks; then solve_factored_rhs(x) solves H x = b (b must stay valid until then).
  /// eliminated_shift (H's row order, may be null): added to the diagonal of each eliminated
  /// block C_e as it is read (C_e + diag(shift_e)); the other rows of it are not read.
  bool factorize(const BlockSparseMatrix& A, const double* b, const double* eliminated_shift = nullptr);
  void solve_factored_rhs(double* x);
  /// solve_factored_rhs in two steps, for a caller that fuses the back-substitution with its own
  /// pass over the eliminated blocks: solve_factored_kept solves the reduced system (x's kept
  /// rows written, the eliminated rows untouched); then back_substitute(e_begin, e_end, x) writes
  /// x_e = C_e⁻¹ (b_e − Σ_k E_keᵀ x_k) for the eliminated blocks [e_begin, e_end) (numbered in
  /// H's block order), serially (no pool: call it from the caller's parallel pass, disjoint
  /// ranges). It reads only the E blocks of those e in H (which may change elsewhere meanwhile)
  /// and C_e⁻¹: once it returned, the caller may overwrite them. Same bits as solve_factored_rhs.
  void solve_factored_kept(double* x);
  void back_substitute(int e_begin, int e_end, double* x);
  void solve(const double* b, double* x) override;
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) override;
  double inverse_factor_norm2(const double* v) override;
  const CholeskyStats& stats() const override { return stats_; }

  /// Marginalization (the VIO window's prior): after analyze(A) with method kDense (or kAuto
  /// resolved to it), forms S = B − E C⁻¹ Eᵀ and rhs = b_k − E C⁻¹ b_e densely over the kept
  /// blocks in H's order, without factorizing S (it may be singular: unobservable directions).
  /// False if some C_e is not positive definite; throws std::logic_error for other methods.
  bool reduced_system(const BlockSparseMatrix& A, const double* b, Eigen::MatrixXd* S, Eigen::VectorXd* rhs);

  SchurMethod method() const { return method_; }  ///< the method used (kAuto resolved)
  int reduced_dim() const;
  int num_eliminated() const;
  /// PCG iterations of the last solve (0 for the direct methods) and in total.
  int last_pcg_iterations() const { return last_pcg_iterations_; }
  long total_pcg_iterations() const { return total_pcg_iterations_; }
  /// x_kᵀ (rhs − S x_k) for the last solve's reduced solution x_k: 0 for the direct methods; for
  /// PCG from x₀ = 0 also 0 up to rounding (CG keeps its residual orthogonal to its iterates,
  /// truncated or not). With x = (x_e back-substituted, x_k), xᵀ H x = bᵀx − this, so a
  /// quadratic model needs no product with H (the LM loop's predicted reduction).
  double last_residual_dot_solution() const { return last_residual_dot_solution_; }
  /// Time spent forming S (or the preconditioner) and factorizing it, in the last factorize().
  double last_schur_time_s() const { return last_schur_time_s_; }
  double last_factor_time_s() const { return last_factor_time_s_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<char> eliminate_;
  const ThreadPool& pool_;
  SchurOptions options_;
  SchurMethod method_ = SchurMethod::kAuto;
  CholeskyStats stats_;
  int last_pcg_iterations_ = 0;
  long total_pcg_iterations_ = 0;
  double last_schur_time_s_ = 0.0, last_factor_time_s_ = 0.0, last_residual_dot_solution_ = 0.0;
};

}  // namespace slamkit
