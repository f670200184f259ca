// SchurComplementSolver against a dense solve of the full system: every method, general block
// sizes (kept–kept blocks included), bit-identical results for any thread count, vᵀH⁻¹v, and
// the structural requirements.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstring>
#include <random>

#include "slamkit/linear/schur_complement.h"

namespace slamkit {
namespace {

struct TestSystem {
  BlockSparseMatrix H;
  Eigen::MatrixXd dense;
  std::vector<char> eliminate;
};

// ne eliminated blocks of size de first, then kept blocks of the given sizes; each eliminated
// block is tied to 2–3 kept blocks, and kept pairs (0,1), (2, last) are tied directly.
TestSystem make_system(int ne, int de, const std::vector<int>& kept, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n;
  std::vector<int> dims(ne, de);
  dims.insert(dims.end(), kept.begin(), kept.end());
  const int nb = static_cast<int>(dims.size());
  std::vector<int> start(nb + 1, 0);
  for (int b = 0; b < nb; ++b) start[b + 1] = start[b] + dims[b];
  const int N = start[nb];
  std::vector<std::vector<int>> factors;
  std::uniform_int_distribution<int> pick(0, static_cast<int>(kept.size()) - 1);
  for (int e = 0; e < ne; ++e) {
    std::vector<int> f = {e};
    const int m = 2 + e % 2;
    while (static_cast<int>(f.size()) < m + 1) {
      const int k = ne + pick(rng);
      if (std::find(f.begin(), f.end(), k) == f.end()) f.push_back(k);
    }
    factors.push_back(f);
  }
  factors.push_back({ne + 0, ne + 1});
  factors.push_back({ne + 2, nb - 1});
  Eigen::MatrixXd D = 0.1 * Eigen::MatrixXd::Identity(N, N);
  std::vector<std::pair<int, int>> pattern;
  for (const auto& f : factors) {
    int cols = 0;
    for (int b : f) cols += dims[b];
    const Eigen::MatrixXd J = Eigen::MatrixXd::NullaryExpr(cols + 2, cols, [&] { return n(rng); });
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    int ra = 0;
    for (int a : f) {
      int rb = 0;
      for (int b : f) {
        D.block(start[a], start[b], dims[a], dims[b]) += JtJ.block(ra, rb, dims[a], dims[b]);
        if (a > b) pattern.emplace_back(a, b);
        rb += dims[b];
      }
      ra += dims[a];
    }
  }
  TestSystem s{BlockSparseMatrix(dims, pattern), D, std::vector<char>(nb, 0)};
  for (int e = 0; e < ne; ++e) s.eliminate[e] = 1;
  for (int j = 0; j < nb; ++j)
    for (const int* i = s.H.column_blocks_begin(j); i != s.H.column_blocks_end(j); ++i)
      s.H.block(*i, j) = D.block(start[*i], start[j], dims[*i], dims[j]);
  return s;
}

Eigen::VectorXd solve_with(TestSystem& s, SchurOptions o, int threads, Eigen::VectorXd b, double* q = nullptr) {
  ThreadPool pool(threads);
  SchurComplementSolver solver(s.eliminate, pool, o);
  solver.analyze(s.H);
  EXPECT_TRUE(solver.factorize(s.H));
  Eigen::VectorXd x(b.size());
  solver.solve(b.data(), x.data());
  if (q) *q = solver.inverse_factor_norm2(b.data());
  return x;
}

TEST(SchurComplement, EveryMethodMatchesTheDenseSolve) {
  for (const auto& kept : {std::vector<int>{9, 9, 9, 9, 9}, std::vector<int>{6, 6, 2, 6, 4}}) {
    TestSystem s = make_system(40, 3, kept, 5);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(s.dense.rows(), -1.0, 2.0);
    const Eigen::VectorXd ref = s.dense.llt().solve(b);
    for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg, SchurMethod::kAuto}) {
      SchurOptions o;
      o.method = m;
      o.pcg_tolerance = 1e-12, o.pcg_q_tolerance = 0.0;
      double q = 0.0;
      const Eigen::VectorXd x = solve_with(s, o, 2, b, &q);
      EXPECT_LT((x - ref).norm(), 1e-8 * ref.norm()) << to_string(m) << " kept dims " << kept[2];
      EXPECT_NEAR(q, b.dot(ref), 1e-8 * std::abs(b.dot(ref))) << to_string(m);
    }
    SchurOptions bj;
    bj.method = SchurMethod::kPcg;
    bj.preconditioner = SchurPreconditioner::kBlockJacobi;
    bj.pcg_tolerance = 1e-12, bj.pcg_q_tolerance = 0.0;
    EXPECT_LT((solve_with(s, bj, 1, b) - ref).norm(), 1e-8 * ref.norm());
  }
}

// factorize(H, b) forms the reduced rhs with S; solve_factored_rhs must give the plain solve's
// answer up to rounding (the rhs sums the same terms in another grouping), for 1 and 2
// threads; without a factorize(H, b) it refuses.
TEST(SchurComplement, RhsFormedWithTheFactorizationMatchesThePlainSolve) {
  TestSystem s = make_system(60, 3, {9, 9, 9, 9, 9, 9}, 11);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(s.dense.rows(), -2.0, 1.0);
  const Eigen::VectorXd ref = s.dense.llt().solve(b);
  for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
    for (auto pre : {SchurPreconditioner::kSchurJacobi, SchurPreconditioner::kBlockJacobi}) {
      if (m != SchurMethod::kPcg && pre == SchurPreconditioner::kBlockJacobi) continue;
      SchurOptions o;
      o.method = m, o.preconditioner = pre;
      o.pcg_tolerance = 1e-12, o.pcg_q_tolerance = 0.0;
      for (int threads : {1, 2}) {
        ThreadPool pool(threads);
        SchurComplementSolver solver(s.eliminate, pool, o);
        solver.analyze(s.H);
        Eigen::VectorXd x_fused(b.size()), x_plain(b.size());
        ASSERT_TRUE(solver.factorize(s.H));
        EXPECT_THROW(solver.solve_factored_rhs(x_fused.data()), std::logic_error);
        solver.solve(b.data(), x_plain.data());
        ASSERT_TRUE(solver.factorize(s.H, b.data()));
        solver.solve_factored_rhs(x_fused.data());
        const std::string what = std::string(to_string(m)) + " threads " + std::to_string(threads);
        EXPECT_LT((x_fused - ref).norm(), 1e-8 * ref.norm()) << what;
        EXPECT_LT((x_fused - x_plain).norm(), 1e-12 * ref.norm()) << what;
      }
    }
  }
}

// solve_factored_kept then back_substitute over disjoint ranges (any order) gives the bits of
// solve_factored_rhs; back_substitute before a reduced solve refuses.
TEST(SchurComplement, BackSubstitutionByRangesMatchesSolveFactoredRhs) {
  TestSystem s = make_system(60, 3, {9, 9, 9, 9, 9, 9}, 13);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(s.dense.rows(), -1.0, 2.0);
  for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
    SchurOptions o;
    o.method = m;
    ThreadPool pool(2);
    SchurComplementSolver solver(s.eliminate, pool, o);
    solver.analyze(s.H);
    Eigen::VectorXd whole(b.size()), ranges = Eigen::VectorXd::Constant(b.size(), 7.0);
    ASSERT_TRUE(solver.factorize(s.H, b.data()));
    EXPECT_THROW(solver.back_substitute(0, 10, ranges.data()), std::logic_error);
    solver.solve_factored_rhs(whole.data());
    ASSERT_TRUE(solver.factorize(s.H, b.data()));
    solver.solve_factored_kept(ranges.data());
    EXPECT_EQ(ranges.head(3 * 60), Eigen::VectorXd::Constant(3 * 60, 7.0)) << "eliminated rows untouched";
    for (int e0 : {40, 0, 17}) solver.back_substitute(e0, e0 == 40 ? 60 : e0 == 0 ? 17 : 40, ranges.data());
    EXPECT_EQ(whole, ranges) << to_string(m);
  }
}

// The Nash-Sofer test stops PCG well before a tight residual tolerance would, with a step
// whose model value is within its tolerance of the exact one.
// factorize(H, b, shift) adds shift to the eliminated blocks' diagonals as it reads them: the
// same bits as the shift written into H's diagonal (the BAL LM damps the points this way).
TEST(SchurComplement, EliminatedShiftEqualsDampingInH) {
  TestSystem s = make_system(40, 3, {9, 9, 9, 9, 9}, 5);
  const int n = s.dense.rows();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd shift = Eigen::VectorXd::LinSpaced(n, 0.5, 3.0);
  BlockSparseMatrix damped = s.H;
  for (int a = 0; a < 40 * 3; ++a) damped.values()[damped.diagonal_positions()[a]] += shift[a];
  for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
    SchurOptions o;
    o.method = m;
    ThreadPool pool(1);
    Eigen::VectorXd x_h(n), x_shift(n);
    SchurComplementSolver in_h(s.eliminate, pool, o), shifted(s.eliminate, pool, o);
    in_h.analyze(damped);
    shifted.analyze(s.H);
    ASSERT_TRUE(in_h.factorize(damped, b.data()));
    in_h.solve_factored_rhs(x_h.data());
    ASSERT_TRUE(shifted.factorize(s.H, b.data(), shift.data()));
    shifted.solve_factored_rhs(x_shift.data());
    EXPECT_EQ(x_h, x_shift) << to_string(m);
  }
}

TEST(SchurComplement, PcgQuadraticModelTestStopsEarlyWithAGoodStep) {
  TestSystem s = make_system(400, 3, std::vector<int>(30, 9), 3);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(s.dense.rows(), -1.0, 1.0);
  const Eigen::VectorXd ref = s.dense.llt().solve(b);
  auto model = [&](const Eigen::VectorXd& x) { return 0.5 * x.dot(s.dense * x) - b.dot(x); };
  ThreadPool pool(1);
  SchurOptions tight;
  tight.method = SchurMethod::kPcg, tight.pcg_tolerance = 1e-10, tight.pcg_q_tolerance = 0.0;
  SchurOptions ns = tight;
  ns.pcg_q_tolerance = 0.1;
  int its[2];
  Eigen::VectorXd x[2];
  for (int k = 0; k < 2; ++k) {
    SchurComplementSolver solver(s.eliminate, pool, k == 0 ? tight : ns);
    solver.analyze(s.H);
    ASSERT_TRUE(solver.factorize(s.H, b.data()));
    x[k].resize(b.size());
    solver.solve_factored_rhs(x[k].data());
    its[k] = solver.last_pcg_iterations();
    // xᵀHx = bᵀx − x_kᵀ(rhs − S x_k): the LM loop's quadratic model without a product with H.
    const double xHx = x[k].dot(s.dense * x[k]);
    EXPECT_NEAR(b.dot(x[k]) - solver.last_residual_dot_solution(), xHx, 1e-9 * xHx);
    // CG from x₀ = 0 keeps r ⟂ x_k (Galerkin), truncated or not: the correction is rounding only.
    EXPECT_LT(std::abs(solver.last_residual_dot_solution()), 1e-9 * xHx);
  }
  EXPECT_LT(its[1], its[0]);
  EXPECT_LT((x[0] - ref).norm(), 1e-7 * ref.norm());
  // Q(x) − Q* = ½‖x − x*‖²_H ≥ 0; the truncated step keeps most of the model decrease.
  EXPECT_LT(model(x[1]) - model(ref), 0.1 * std::abs(model(ref)));
}

TEST(SchurComplement, ResultsDoNotDependOnTheThreadCount) {
  TestSystem s = make_system(300, 3, std::vector<int>(12, 9), 7);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(s.dense.rows(), -3.0, 1.0);
  for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
    SchurOptions o;
    o.method = m;
    const Eigen::VectorXd x1 = solve_with(s, o, 1, b), x2 = solve_with(s, o, 2, b), x3 = solve_with(s, o, 3, b);
    EXPECT_EQ(0, std::memcmp(x1.data(), x2.data(), sizeof(double) * x1.size())) << to_string(m);
    EXPECT_EQ(0, std::memcmp(x1.data(), x3.data(), sizeof(double) * x1.size())) << to_string(m);
  }
}

TEST(SchurComplement, AutoPicksDenseForSmallAndSparseForLarger) {
  TestSystem s = make_system(300, 3, std::vector<int>(12, 9), 7);
  ThreadPool pool(1);
  SchurComplementSolver small(s.eliminate, pool);
  small.analyze(s.H);
  EXPECT_EQ(small.method(), SchurMethod::kDense);
  SchurOptions o;
  o.auto_dense_max_dim = 50;
  SchurComplementSolver large(s.eliminate, pool, o);
  large.analyze(s.H);
  EXPECT_EQ(large.method(), SchurMethod::kCholesky);
  o.auto_pcg_min_flops = 1.0;
  SchurComplementSolver huge(s.eliminate, pool, o);
  huge.analyze(s.H);
  EXPECT_EQ(huge.method(), SchurMethod::kPcg);
}

TEST(SchurComplement, RejectsStructuresItCannotEliminate) {
  ThreadPool pool(1);
  // Two eliminated blocks tied together.
  BlockSparseMatrix H({3, 3, 9}, {{1, 0}, {2, 0}, {2, 1}});
  EXPECT_THROW(SchurComplementSolver({1, 1, 0}, pool).analyze(H), std::invalid_argument);
  // An eliminated block after its neighbour.
  BlockSparseMatrix G({9, 3}, {{1, 0}});
  EXPECT_THROW(SchurComplementSolver({0, 1}, pool).analyze(G), std::invalid_argument);
  // A singular eliminated block: factorize reports failure instead of producing NaN.
  BlockSparseMatrix F({3, 9}, {{1, 0}});
  F.set_zero();
  F.block(1, 1) = Eigen::MatrixXd::Identity(9, 9);
  SchurComplementSolver solver({1, 0}, pool);
  solver.analyze(F);
  EXPECT_FALSE(solver.factorize(F));
  // Indefinite (the third pivot of the 3×3 LDLᵀ negative) and NaN eliminated blocks: rejected too.
  Eigen::Matrix3d C;
  C << 4, 2, 2, 2, 2, 2, 2, 2, 1;  // d0 = 4, d1 = 1, d2 = -1
  F.block(0, 0) = C;
  EXPECT_FALSE(solver.factorize(F));
  C(2, 2) = 3;  // d2 = 1: positive definite, accepted
  F.block(0, 0) = C;
  EXPECT_TRUE(solver.factorize(F));
  C(1, 1) = std::nan("");
  F.block(0, 0) = C;
  EXPECT_FALSE(solver.factorize(F));
}

}  // namespace
}  // namespace slamkit
