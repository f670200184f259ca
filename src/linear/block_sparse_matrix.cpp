#include "slamkit/linear/block_sparse_matrix.h"

#include <algorithm>
#include <limits>
#include <string>
#include <stdexcept>

namespace slamkit {

BlockSparseMatrix::BlockSparseMatrix(std::vector<int> block_dims, std::vector<std::pair<int, int>> blocks)
    : block_dims_(std::move(block_dims)) {
  const int nb = num_blocks();

  for (auto& [i, j] : blocks) {
    if (i < j) std::swap(i, j);  // lower triangle: i ≥ j
    if (j < 0 || i >= nb) throw std::out_of_range("BlockSparseMatrix: block index out of range");
  }
  for (int i = 0; i < nb; ++i) blocks.emplace_back(i, i);
  // Sort by (column, row) and drop duplicates: two stable counting sorts (by row, then by
  // column), O(blocks + nb) instead of a comparison sort.
  {
    std::vector<std::pair<int, int>> by_row(blocks.size());
    std::vector<std::size_t> start(static_cast<std::size_t>(nb) + 1, 0);
    for (const auto& b : blocks) ++start[b.first + 1];
    for (int k = 0; k < nb; ++k) start[k + 1] += start[k];
    for (const auto& b : blocks) by_row[start[b.first]++] = b;
    std::fill(start.begin(), start.end(), 0);
    for (const auto& b : by_row) ++start[b.second + 1];
    for (int k = 0; k < nb; ++k) start[k + 1] += start[k];
    for (const auto& b : by_row) blocks[start[b.second]++] = b;
  }
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());

  block_col_ptr_.assign(nb + 1, 0);
  block_rows_.reserve(blocks.size());
  for (const auto& [i, j] : blocks) {
    if (i < 0 || j >= nb) throw std::out_of_range("BlockSparseMatrix: block index out of range");
    ++block_col_ptr_[j + 1];
    block_rows_.push_back(i);
  }
  for (int j = 0; j < nb; ++j) block_col_ptr_[j + 1] += block_col_ptr_[j];
  lay_out_values();
}

BlockSparseMatrix::BlockSparseMatrix(const BlockSparseMatrix& pattern, std::vector<int> block_dims)
    : block_dims_(std::move(block_dims)), block_col_ptr_(pattern.block_col_ptr_), block_rows_(pattern.block_rows_) {
  if (num_blocks() != pattern.num_blocks())
    throw std::invalid_argument("BlockSparseMatrix: " + std::to_string(num_blocks()) + " block sizes for a pattern of " +
                                std::to_string(pattern.num_blocks()) + " blocks");
  lay_out_values();
}

void BlockSparseMatrix::lay_out_values() {
  const int nb = num_blocks();
  block_starts_.resize(nb + 1);
  block_starts_[0] = 0;
  for (int i = 0; i < nb; ++i) block_starts_[i + 1] = block_starts_[i] + block_dims_[i];
  rows_ = block_starts_[nb];
  // Every scalar column of block column j has the same row list, col_heights_[j] rows long.
  col_heights_.assign(nb, 0);
  std::size_t nnz = 0;
  for (int j = 0; j < nb; ++j) {
    for (int k = block_col_ptr_[j]; k < block_col_ptr_[j + 1]; ++k) col_heights_[j] += block_dims_[block_rows_[k]];
    nnz += static_cast<std::size_t>(col_heights_[j]) * block_dims_[j];
  }
  if (nnz > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("BlockSparseMatrix: more than 2^31 nonzeros");
  values_.assign(nnz, 0.0);
  block_value_offset_.resize(block_rows_.size());
  diag_pos_.resize(rows_);
  std::ptrdiff_t pos = 0;
  for (int j = 0; j < nb; ++j) {
    const std::ptrdiff_t base = pos;
    std::ptrdiff_t row_offset = 0;
    for (int k = block_col_ptr_[j]; k < block_col_ptr_[j + 1]; ++k) {
      block_value_offset_[k] = base + row_offset;
      if (block_rows_[k] == j)  // the diagonal block comes first in its column
        for (int c = 0; c < block_dims_[j]; ++c)
          diag_pos_[block_starts_[j] + c] = base + row_offset + static_cast<std::ptrdiff_t>(c) * col_heights_[j] + c;
      row_offset += block_dims_[block_rows_[k]];
    }
    pos += row_offset * block_dims_[j];
  }
}

void BlockSparseMatrix::build_scalar_index() const {
  if (!col_ptr_.empty()) return;
  // Scalar CSC: every column of block column j has the same row list.
  col_ptr_.resize(rows_ + 1);
  row_index_.resize(values_.size());
  int pos = 0;
  for (int j = 0; j < num_blocks(); ++j)
    for (int c = 0; c < block_dims_[j]; ++c) {
      col_ptr_[block_starts_[j] + c] = pos;
      for (int k = block_col_ptr_[j]; k < block_col_ptr_[j + 1]; ++k) {
        const int i = block_rows_[k];
        for (int r = 0; r < block_dims_[i]; ++r) row_index_[pos++] = block_starts_[i] + r;
      }
    }
  col_ptr_[rows_] = pos;
}

const std::vector<int>& BlockSparseMatrix::col_ptr() const {
  build_scalar_index();
  return col_ptr_;
}

const std::vector<int>& BlockSparseMatrix::row_index() const {
  build_scalar_index();
  return row_index_;
}

std::ptrdiff_t BlockSparseMatrix::block_offset(int i, int j) const {
  // The diagonal block comes first in its column (most look-ups: assembly, initialization).
  if (i == j) return block_value_offset_[block_col_ptr_[j]];
  const int* begin = column_blocks_begin(j);
  const int* end = column_blocks_end(j);
  const int* it = std::lower_bound(begin, end, i);
  if (it == end || *it != i) return -1;
  return block_value_offset_[block_col_ptr_[j] + (it - begin)];
}

BlockSparseMatrix::BlockMap BlockSparseMatrix::block(int i, int j) {
  const std::ptrdiff_t off = block_offset(i, j);
  if (off < 0) throw std::out_of_range("BlockSparseMatrix: block not in pattern");
  return BlockMap(values_.data() + off, block_dims_[i], block_dims_[j], Eigen::OuterStride<>(col_heights_[j]));
}

void BlockSparseMatrix::set_zero() { std::fill(values_.begin(), values_.end(), 0.0); }

void BlockSparseMatrix::multiply(const double* x, double* y) const {
  std::fill(y, y + rows_, 0.0);
  for (int j = 0; j < num_blocks(); ++j) {
    const int dj = block_dims_[j], sj = block_starts_[j];
    for (int k = block_col_ptr_[j]; k < block_col_ptr_[j + 1]; ++k) {
      const int i = block_rows_[k], di = block_dims_[i], si = block_starts_[i];
      const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> B(
          values_.data() + block_value_offset_[k], di, dj, Eigen::OuterStride<>(col_heights_[j]));
      Eigen::Map<Eigen::VectorXd>(y + si, di).noalias() += B * Eigen::Map<const Eigen::VectorXd>(x + sj, dj);
      if (i != j)  // the mirrored upper block
        Eigen::Map<Eigen::VectorXd>(y + sj, dj).noalias() += B.transpose() * Eigen::Map<const Eigen::VectorXd>(x + si, di);
    }
  }
}

Eigen::MatrixXd BlockSparseMatrix::to_dense() const {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(rows_, rows_);
  for (int j = 0; j < num_blocks(); ++j) {
    for (int k = block_col_ptr_[j]; k < block_col_ptr_[j + 1]; ++k) {
      const int i = block_rows_[k];
      const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> B(
          values_.data() + block_value_offset_[k], block_dims_[i], block_dims_[j], Eigen::OuterStride<>(col_heights_[j]));
      D.block(block_starts_[i], block_starts_[j], block_dims_[i], block_dims_[j]) = B;
      if (i != j) D.block(block_starts_[j], block_starts_[i], block_dims_[j], block_dims_[i]) = B.transpose();
    }
  }
  return D;
}

}  // namespace slamkit
