#include "slamkit/linear/block_sparse_matrix.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

namespace slamkit {
namespace {

// A random symmetric block matrix with mixed block sizes and a given pattern.
BlockSparseMatrix random_matrix(std::mt19937& rng) {
  const std::vector<int> dims = {3, 6, 2, 6, 1, 3};
  BlockSparseMatrix A(dims, {{0, 1}, {3, 1}, {1, 1}, {2, 5}, {0, 5}, {4, 3}, {0, 1}});
  std::normal_distribution<double> n;
  for (int j = 0; j < A.num_blocks(); ++j) {
    for (const int* it = A.column_blocks_begin(j); it != A.column_blocks_end(j); ++it) {
      auto B = A.block(*it, j);
      for (int c = 0; c < B.cols(); ++c)
        for (int r = 0; r < B.rows(); ++r) B(r, c) = n(rng);
      if (*it == j) B = (B + B.transpose()).eval() + 20.0 * Eigen::MatrixXd::Identity(B.rows(), B.cols());
    }
  }
  return A;
}

TEST(BlockSparseMatrix, PatternLayoutAndCsc) {
  std::mt19937 rng(1);
  const BlockSparseMatrix A = random_matrix(rng);
  EXPECT_EQ(A.rows(), 21);
  EXPECT_EQ(A.num_stored_blocks(), 6u + 5u);  // diagonal + distinct off-diagonal
  EXPECT_LT(A.block_offset(0, 5), 0);         // the upper triangle is not stored
  EXPECT_GE(A.block_offset(5, 0), 0);
  EXPECT_LT(A.block_offset(2, 1), 0);
  // CSC rows are sorted and the diagonal positions point at diagonal entries.
  const Eigen::MatrixXd D = A.to_dense();
  for (int c = 0; c < A.rows(); ++c) {
    for (int k = A.col_ptr()[c]; k + 1 < A.col_ptr()[c + 1]; ++k) EXPECT_LT(A.row_index()[k], A.row_index()[k + 1]);
    for (int k = A.col_ptr()[c]; k < A.col_ptr()[c + 1]; ++k)
      EXPECT_EQ(A.values()[k], D(A.row_index()[k], c));
    EXPECT_EQ(A.values()[A.diagonal_positions()[c]], D(c, c));
  }
  EXPECT_TRUE(D.isApprox(D.transpose()));
}

// The same pattern with other block sizes equals building it from the pairs again.
TEST(BlockSparseMatrix, SamePatternOtherBlockSizes) {
  const std::vector<std::pair<int, int>> pairs = {{0, 1}, {3, 1}, {2, 5}, {0, 5}, {4, 3}, {0, 1}};
  const BlockSparseMatrix A(std::vector<int>(6, 1), pairs);
  const std::vector<int> dims = {2, 2, 3, 2, 1, 2};
  const BlockSparseMatrix B(A, dims), C(dims, pairs);
  EXPECT_EQ(B.block_column_pointers(), C.block_column_pointers());
  EXPECT_EQ(B.block_row_indices(), C.block_row_indices());
  EXPECT_EQ(B.rows(), C.rows());
  EXPECT_EQ(B.nnz(), C.nnz());
  EXPECT_EQ(B.diagonal_positions(), C.diagonal_positions());
  EXPECT_EQ(B.col_ptr(), C.col_ptr());
  EXPECT_EQ(B.row_index(), C.row_index());
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) EXPECT_EQ(B.block_offset(i, j), C.block_offset(i, j)) << i << "," << j;
  EXPECT_THROW(BlockSparseMatrix(A, std::vector<int>(5, 2)), std::invalid_argument);
}

TEST(BlockSparseMatrix, MultiplyMatchesDense) {
  std::mt19937 rng(2);
  const BlockSparseMatrix A = random_matrix(rng);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  Eigen::VectorXd y(A.rows());
  A.multiply(x.data(), y.data());
  EXPECT_TRUE(y.isApprox(A.to_dense() * x, 1e-13));
}

}  // namespace
}  // namespace slamkit
