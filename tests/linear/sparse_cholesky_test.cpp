#include "slamkit/linear/sparse_cholesky.h"

#include <algorithm>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

namespace slamkit {
namespace {

// SPD matrix with the sparsity of a random pose graph (chain + loop closures), blocks of 6.
BlockSparseMatrix pose_graph_like(int n, int loops, std::mt19937& rng) {
  std::vector<std::pair<int, int>> pattern;
  for (int i = 0; i + 1 < n; ++i) pattern.emplace_back(i, i + 1);
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int k = 0; k < loops; ++k) pattern.emplace_back(pick(rng), pick(rng));
  BlockSparseMatrix A(std::vector<int>(n, 6), pattern);
  // Fill as Σ JᵀJ of random 6×12 "edges" so that A is SPD.
  std::normal_distribution<double> nd;
  for (int j = 0; j < n; ++j) A.block(j, j) = 4.0 * Eigen::MatrixXd::Identity(6, 6);
  for (auto [a, b] : pattern) {
    if (a == b) continue;
    if (a < b) std::swap(a, b);  // lower triangle: (larger, smaller)
    Eigen::MatrixXd J(6, 12);
    for (int c = 0; c < 12; ++c)
      for (int r = 0; r < 6; ++r) J(r, c) = nd(rng);
    A.block(a, a) += J.leftCols(6).transpose() * J.leftCols(6);
    A.block(b, b) += J.rightCols(6).transpose() * J.rightCols(6);
    A.block(a, b) += J.leftCols(6).transpose() * J.rightCols(6);
  }
  return A;
}

class SparseCholeskyTest : public ::testing::TestWithParam<std::tuple<SparseBackend, OrderingMethod>> {};

TEST_P(SparseCholeskyTest, SolvesLikeDense) {
  const auto [backend, ordering] = GetParam();
  if (backend == SparseBackend::kCholmod && !cholmod_available()) GTEST_SKIP() << "SKIPPED: no CHOLMOD in this build";
  std::mt19937 rng(5);
  BlockSparseMatrix A = pose_graph_like(60, 25, rng);
  auto solver = make_sparse_cholesky(backend, ordering);
  solver->analyze(A);
  ASSERT_TRUE(solver->factorize(A));
  const Eigen::MatrixXd D = A.to_dense();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -3.0, 5.0);
  Eigen::VectorXd x(A.rows());
  solver->solve(b.data(), x.data());
  EXPECT_LT((D * x - b).norm() / b.norm(), 1e-12);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 3);
  EXPECT_LT((D * solver->solve(B) - B).norm() / B.norm(), 1e-12);
  // ‖L⁻¹ P v‖² = vᵀ A⁻¹ v for any LLᵀ factor of P A Pᵀ.
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(A.rows(), 1.0, 2.0);
  EXPECT_NEAR(solver->inverse_factor_norm2(v.data()), v.dot(D.llt().solve(v)), 1e-10 * v.squaredNorm());
  // Refactorizing new values with the same pattern works without re-analysis.
  for (double& val : A.values()) val *= 2.0;
  ASSERT_TRUE(solver->factorize(A));
  Eigen::VectorXd x2(A.rows());
  solver->solve(b.data(), x2.data());
  EXPECT_TRUE(x2.isApprox(0.5 * x, 1e-11));
  EXPECT_FALSE(solver->stats().ordering.empty());
}

TEST_P(SparseCholeskyTest, ReportsIndefiniteMatrix) {
  const auto [backend, ordering] = GetParam();
  if (backend == SparseBackend::kCholmod && !cholmod_available()) GTEST_SKIP() << "SKIPPED: no CHOLMOD in this build";
  std::mt19937 rng(6);
  BlockSparseMatrix A = pose_graph_like(20, 5, rng);
  A.values()[A.diagonal_positions()[40]] = -100.0;
  auto solver = make_sparse_cholesky(backend, ordering);
  solver->analyze(A);
  EXPECT_FALSE(solver->factorize(A));
}

TEST(SparseCholesky, StoredInEliminationOrderEqualsPermutedSolve) {
  // The same SPD system factorized as stored (natural) and through a given block order.
  std::mt19937 rng(8);
  BlockSparseMatrix A = pose_graph_like(50, 20, rng);
  std::vector<std::pair<int, int>> edges;
  for (int j = 0; j < A.num_blocks(); ++j)
    for (const int* i = A.column_blocks_begin(j); i != A.column_blocks_end(j); ++i) edges.emplace_back(*i, j);
  const EliminationOrder order = compute_elimination_order(A.num_blocks(), edges, OrderingMethod::kAmd);
  ASSERT_EQ(order.order.size(), static_cast<std::size_t>(A.num_blocks()));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  Eigen::VectorXd x1(A.rows()), x2(A.rows());
  auto stored = make_sparse_cholesky(SparseBackend::kAuto);
  stored->analyze(A);
  ASSERT_TRUE(stored->factorize(A));
  stored->solve(b.data(), x1.data());
  auto permuted = make_sparse_cholesky(SparseBackend::kAuto);
  permuted->analyze(A, &order);
  ASSERT_TRUE(permuted->factorize(A));
  permuted->solve(b.data(), x2.data());
  EXPECT_TRUE(x1.isApprox(x2, 1e-10));
  EXPECT_LT(permuted->stats().factor_nnz, stored->stats().factor_nnz);  // the order reduces fill
}

bool is_permutation_of_n(const std::vector<int>& order, int n) {
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < n; ++k)
    if (k >= static_cast<int>(sorted.size()) || sorted[k] != k) return false;
  return static_cast<int>(sorted.size()) == n;
}

// AMD after eliminating chains (degree ≤ 2 nodes) first: on graphs whose minimum fill is
// known, the order reaches it; where chains are a minority or hang on a hub, AMD alone orders.
TEST(EliminationOrder, ChainsAreEliminatedWithoutExtraFill) {
  const int n = 500;
  // A ring: the best order fills n − 3 edges; column counts 3 for all but the last two (2, 1).
  std::vector<std::pair<int, int>> ring;
  for (int i = 0; i < n; ++i) ring.emplace_back(i, (i + 1) % n);
  const EliminationOrder r = compute_elimination_order(n, ring, OrderingMethod::kAmd);
  ASSERT_TRUE(is_permutation_of_n(r.order, n));
  EXPECT_DOUBLE_EQ(r.flops, 9.0 * (n - 2) + 4.0 + 1.0);
  // A chain with two loop closures (a pose graph in miniature): a valid order whose fill is
  // that of three joined cycles, at most a few entries per closure beyond the chain's.
  std::vector<std::pair<int, int>> loops;
  for (int i = 0; i + 1 < n; ++i) loops.emplace_back(i, i + 1);
  loops.emplace_back(0, 250);
  loops.emplace_back(100, 400);
  const EliminationOrder l = compute_elimination_order(n, loops, OrderingMethod::kAmd);
  ASSERT_TRUE(is_permutation_of_n(l.order, n));
  EXPECT_LE(l.flops, 9.0 * n + 100.0);
  // A hub with 200 chains of 3 nodes to a ring around it: chain nodes next to the hub are left
  // to AMD (bounded work); the order is still a permutation and the factorization solves.
  std::vector<std::pair<int, int>> hub;
  const int arms = 200, m = 1 + 3 * arms;
  for (int a = 0; a < arms; ++a) {
    const int first = 1 + 3 * a;
    hub.emplace_back(0, first);
    hub.emplace_back(first, first + 1);
    hub.emplace_back(first + 1, first + 2);
    hub.emplace_back(first + 2, 1 + 3 * ((a + 1) % arms) + 2);
  }
  const EliminationOrder h = compute_elimination_order(m, hub, OrderingMethod::kAmd);
  ASSERT_TRUE(is_permutation_of_n(h.order, m));
  BlockSparseMatrix A(std::vector<int>(m, 2), hub);
  for (int j = 0; j < m; ++j) A.block(j, j) = 2.5 * Eigen::MatrixXd::Identity(2, 2) * (j == 0 ? arms : 1);
  for (auto [a, b] : hub) A.block(std::max(a, b), std::min(a, b)) = -0.5 * Eigen::MatrixXd::Identity(2, 2);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 1.0);
  Eigen::VectorXd x(A.rows());
  auto chol = make_sparse_cholesky(SparseBackend::kAuto);
  chol->analyze(A, &h);
  ASSERT_TRUE(chol->factorize(A));
  chol->solve(rhs.data(), x.data());
  Eigen::VectorXd Ax(A.rows());
  A.multiply(x.data(), Ax.data());
  EXPECT_LT((Ax - rhs).norm(), 1e-9);
}

// A sparse SPD system of D×D blocks (chain + a few loop closures), as Σ JᵀJ.
BlockSparseMatrix sparse_blocks(int n, int d, int loops, std::mt19937& rng) {
  std::vector<std::pair<int, int>> pattern;
  for (int i = 0; i + 1 < n; ++i) pattern.emplace_back(i, i + 1);
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int k = 0; k < loops; ++k) pattern.emplace_back(pick(rng), pick(rng));
  BlockSparseMatrix A(std::vector<int>(n, d), pattern);
  std::normal_distribution<double> nd;
  for (int j = 0; j < n; ++j) A.block(j, j) = 0.5 * Eigen::MatrixXd::Identity(d, d);
  for (auto [a, b] : pattern) {
    if (a == b) continue;
    if (a < b) std::swap(a, b);
    Eigen::MatrixXd J(d, 2 * d);
    for (int c = 0; c < 2 * d; ++c)
      for (int r = 0; r < d; ++r) J(r, c) = nd(rng);
    A.block(a, a) += J.leftCols(d).transpose() * J.leftCols(d);
    A.block(b, b) += J.rightCols(d).transpose() * J.rightCols(d);
    A.block(a, b) += J.leftCols(d).transpose() * J.rightCols(d);
  }
  return A;
}

// Sparse factors of equal-block matrices in stored order take the block simplicial
// factorization (where CHOLMOD would go simplicial); it solves like the dense LLᵀ, with
// several right-hand sides, reports ‖L⁻¹v‖² and indefinite matrices, and refactorizes.
TEST(SparseCholesky, BlockSimplicialSolvesLikeDense) {
  if (!cholmod_available()) GTEST_SKIP() << "SKIPPED: no CHOLMOD in this build";
  for (int d : {1, 2, 3, 6}) {
    std::mt19937 rng(11 + d);
    BlockSparseMatrix A = sparse_blocks(80, d, 6, rng);
    auto solver = make_sparse_cholesky(SparseBackend::kCholmod);
    solver->analyze(A);
    EXPECT_NE(solver->name().find("block simplicial"), std::string::npos) << d;
    ASSERT_TRUE(solver->factorize(A)) << d;
    const Eigen::MatrixXd D = A.to_dense();
    const Eigen::LLT<Eigen::MatrixXd> llt(D);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -3.0, 5.0);
    Eigen::VectorXd x(A.rows());
    solver->solve(b.data(), x.data());
    EXPECT_LT((D * x - b).norm() / b.norm(), 1e-12) << d;
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 3);
    EXPECT_LT((D * solver->solve(B) - B).norm() / B.norm(), 1e-12) << d;
    const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(A.rows(), 1.0, 2.0);
    EXPECT_NEAR(solver->inverse_factor_norm2(v.data()), v.dot(llt.solve(v)), 1e-10 * v.dot(llt.solve(v))) << d;
    // nnz(L) as CHOLMOD counts it (lower triangle of the scalar factor).
    Eigen::MatrixXd L = llt.matrixL();
    EXPECT_EQ(solver->stats().factor_nnz, static_cast<double>((L.array() != 0.0).count())) << d;
    for (double& val : A.values()) val *= 4.0;
    ASSERT_TRUE(solver->factorize(A));
    Eigen::VectorXd x2(A.rows());
    solver->solve(b.data(), x2.data());
    EXPECT_TRUE(x2.isApprox(0.25 * x, 1e-11)) << d;
    A.values()[A.diagonal_positions()[A.rows() / 2]] = -1.0;
    EXPECT_FALSE(solver->factorize(A)) << d;
  }
  // A dense factor (about every block coupled: flops / nnz(L) ≈ 2/3 · 360 scalar columns) stays
  // with CHOLMOD's supernodal factorization.
  std::mt19937 rng(21);
  BlockSparseMatrix dense = sparse_blocks(60, 6, 1200, rng);
  auto solver = make_sparse_cholesky(SparseBackend::kCholmod);
  solver->analyze(dense);
  EXPECT_NE(solver->name().find("supernodal"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(
    Backends, SparseCholeskyTest,
    ::testing::Combine(::testing::Values(SparseBackend::kCholmod, SparseBackend::kEigen),
                       ::testing::Values(OrderingMethod::kAuto, OrderingMethod::kAmd, OrderingMethod::kMetis,
                                         OrderingMethod::kNesdis, OrderingMethod::kNatural)));

}  // namespace
}  // namespace slamkit
