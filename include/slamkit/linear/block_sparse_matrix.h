// BlockSparseMatrix: a symmetric block-sparse matrix stored as its lower block triangle in
// compressed sparse column (CSC) form, ready to hand to CHOLMOD without a copy.
//
// Layout: block column j holds the blocks (i, j), i ≥ j, of its pattern in increasing i;
// every scalar column of block column j lists the same rows (all rows of those blocks, so
// diagonal blocks are stored in full), and block (i, j) is a column-major d_i × d_j matrix at
// values() + block_offset(i, j) with leading dimension leading_dim(j). Diagonal blocks must be
// kept symmetric (multiply() and to_dense() read them whole; the Cholesky backends read their
// lower triangle). The pattern is fixed at construction; values change every iteration.
// Blocks are numbered in elimination order by their owner (NormalEquations), so that CHOLMOD
// factorizes the matrix as stored, without permuting it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace slamkit {

class BlockSparseMatrix {
 public:
  using BlockMap = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

  BlockSparseMatrix() = default;
  /// block_dims[i]: size of block row/column i. blocks: (i, j) pairs in any order, duplicates
  /// allowed, either triangle; every diagonal block is added.
  BlockSparseMatrix(std::vector<int> block_dims, std::vector<std::pair<int, int>> blocks);
  /// The block pattern of `pattern` with other block sizes (one per block), zero values; no
  /// sorting again (the 2D initialization's position system on its orientation system's pattern).
  BlockSparseMatrix(const BlockSparseMatrix& pattern, std::vector<int> block_dims);

  int num_blocks() const { return static_cast<int>(block_dims_.size()); }
  int rows() const { return rows_; }
  int block_dim(int i) const { return block_dims_[i]; }
  int block_start(int i) const { return block_starts_[i]; }
  const std::vector<int>& block_dims() const { return block_dims_; }
  std::size_t num_stored_blocks() const { return block_rows_.size(); }
  std::size_t nnz() const { return values_.size(); }

  /// Offset of block (i, j), i ≥ j, into values(); −1 if the block is not in the pattern.
  std::ptrdiff_t block_offset(int i, int j) const;
  int leading_dim(int j) const { return col_heights_[j]; }
  BlockMap block(int i, int j);  ///< i ≥ j, must exist

  /// The block pattern itself (lower triangle incl. diagonal) in CSC form over blocks.
  const std::vector<int>& block_column_pointers() const { return block_col_ptr_; }
  const std::vector<int>& block_row_indices() const { return block_rows_; }
  /// The block rows i ≥ j of block column j, sorted (the first one is j itself).
  const int* column_blocks_begin(int j) const { return block_rows_.data() + block_col_ptr_[j]; }
  const int* column_blocks_end(int j) const { return block_rows_.data() + block_col_ptr_[j + 1]; }

  void set_zero();
  std::vector<double>& values() { return values_; }
  const std::vector<double>& values() const { return values_; }
  // CSC arrays (lower triangle plus full diagonal blocks), 32-bit as CHOLMOD's int interface.
  // Built on the first call (the block Cholesky never reads them); that first call must not
  // race with another one on the same matrix.
  const std::vector<int>& col_ptr() const;
  const std::vector<int>& row_index() const;
  /// Positions of the scalar diagonal entries in values().
  const std::vector<std::ptrdiff_t>& diagonal_positions() const { return diag_pos_; }

  /// y = A x with A the full symmetric matrix.
  void multiply(const double* x, double* y) const;
  Eigen::MatrixXd to_dense() const;

 private:
  std::vector<int> block_dims_, block_starts_;
  int rows_ = 0;
  std::vector<int> block_col_ptr_, block_rows_;      // block pattern, CSC over blocks
  std::vector<std::ptrdiff_t> block_value_offset_;  // per stored block
  std::vector<int> col_heights_;                    // rows per scalar column of block column j
  mutable std::vector<int> col_ptr_, row_index_;    // scalar CSC, empty until first asked for
  void build_scalar_index() const;
  void lay_out_values();  // block starts, column heights, offsets and zero values from the pattern
  std::vector<std::ptrdiff_t> diag_pos_;
  std::vector<double> values_;
};

}  // namespace slamkit
