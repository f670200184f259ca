// Internal: simplicial Cholesky A = L Lᵀ over the blocks of a BlockSparseMatrix whose blocks
// all have the same size D ∈ {1, 2, 3, 6}, factorized in its stored (elimination) order.
//
// CHOLMOD's simplicial factorization works on scalars: per scalar update it loads an index
// and scatters one value, and its symbolic analysis runs on the scalar pattern (D² times the
// block pattern's entries). Here the elimination tree, the pattern of L and every update are
// per block: L(i, j) −= L(i, k) L(j, k)ᵀ is one fixed-size D×D product. It serves the sparse
// factors (2D pose graphs, parking-garage, the initialization's systems: scalar flops / nnz(L)
// below cholmod_cholesky.cpp's kBlockSwitch, on the counts CHOLMOD computes); denser factors
// keep CHOLMOD's supernodal (BLAS-3) path.
//
// Symbolic analysis (Liu's elimination tree on the block graph, row patterns of L by row
// subtrees): O(nnz(L) blocks). Numeric factorization: left-looking by block columns, with the
// columns that update column j in a linked list (each column k is linked to the row of its next
// off-diagonal block). Serial and deterministic.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "slamkit/linear/block_sparse_matrix.h"

namespace slamkit::detail {

/// The block-pattern part of the symbolic analysis: the pattern analyzed (A's block column
/// pointers and row indices), L's block pattern by columns (rows ascending) and the slot in L's
/// column of each of A's off-diagonal blocks. It does not depend on the block size, so systems
/// over the same block pattern share it (a 2D pose graph's orientation and position systems and
/// its optimizer's H). Immutable once built.
struct BlockSymbolic {
  std::vector<int> a_col_ptr, a_rows;
  std::vector<int> col_start, rows;  // off-diagonal blocks of L by column
  std::vector<int> a_start, a_slot;  // A's off-diagonal blocks of column j → slot in L's column j
  /// Whether this analysis was made for A's block pattern.
  bool matches(const BlockSparseMatrix& A) const;
};

class BlockCholesky {
 public:
  /// Whether A's blocks are all D×D with D ∈ {1, 2, 3, 6}.
  static bool supports(const BlockSparseMatrix& A);
  /// Symbolic analysis of A's pattern as stored (requires supports(A)); adopts `reuse` instead
  /// of analyzing the pattern when it was made for A's block pattern.
  void analyze(const BlockSparseMatrix& A, std::shared_ptr<const BlockSymbolic> reuse = nullptr);
  /// The pattern analysis in use (shareable), and whether analyze() adopted it.
  const std::shared_ptr<const BlockSymbolic>& symbolic() const { return sym_; }
  bool reused_symbolic() const { return reused_; }
  /// Scalar nonzeros of L and CHOLMOD's flop measure Σ_columns (nnz of the column)².
  double factor_nnz() const { return lnz_; }
  double factor_flops() const { return flops_; }
  /// Numeric factorization of A (same pattern as analyzed); false if A is not positive definite.
  bool factorize(const BlockSparseMatrix& A);
  /// x ← A⁻¹ x for `nrhs` column-major right-hand sides with leading dimension rows().
  void solve(double* x, int nrhs) const;
  /// ‖L⁻¹ v‖².
  double inverse_factor_norm2(const double* v) const;
  int rows() const { return n_ * d_; }

 private:
  template <int D>
  bool factorize_fixed(const BlockSparseMatrix& A);
  template <int D>
  void solve_fixed(double* x, int nrhs) const;
  template <int D>
  void forward_fixed(double* x) const;

  static std::shared_ptr<const BlockSymbolic> analyze_pattern(const BlockSparseMatrix& A);

  int n_ = 0, d_ = 0;
  std::shared_ptr<const BlockSymbolic> sym_;
  bool reused_ = false;
  std::vector<std::ptrdiff_t> a_base_;  // offset of A(j, j) in A's values (its column starts there)
  std::vector<double> diag_, off_;     // D×D blocks, column-major: L(j, j) and L(rows_[q], j)
  std::vector<int> map_, head_, link_, next_;  // factorization workspace
  double lnz_ = 0.0, flops_ = 0.0;
};

}  // namespace slamkit::detail
