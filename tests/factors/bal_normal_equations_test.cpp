// BalNormalEquations against the generic NormalEquations of the same factor graph (H, g, cost,
// with and without robust kernels, with a repeated observation), its quadratic form, and the
// direct LM path against the Optimizer on the factor graph; bit-identical for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/factors/bundle_adjustment.h"
#include "slamkit/io/bal_io.h"
#include "slamkit/linear/normal_equations.h"
#include "slamkit/sim/ba_generator.h"

namespace slamkit {
namespace {

BalProblem small_problem(int cameras, int points, unsigned seed = 5) {
  BaSimOptions o;
  o.cameras = cameras, o.points = points, o.seed = seed;
  BalProblem p = generate_ba_problem(o);
  for (std::size_t i = 0; i < p.cameras.size(); ++i) p.cameras[i][7] += 0.05 * (i % 3), p.cameras[i][8] -= 0.01;
  return p;
}

struct Reference {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  double cost;
};

Reference generic_normal_equations(const BalProblem& p, std::shared_ptr<const RobustKernel> kernel) {
  BundleAdjustmentProblem ba = build_bundle_adjustment_problem(p, kernel);
  EliminationOrder order;
  order.method = "points first";
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < ba.values.size(); ++i)
      if (is_bal_point_key(ba.values.key(i)) == (pass == 0)) order.order.push_back(static_cast<int>(i));
  const ThreadPool pool(1);
  NormalEquations ne(ba.graph, ba.values, OrderingMethod::kAuto, &order);
  Reference r;
  r.cost = ne.linearize(ba.values, pool);
  // NormalEquations postorders the points: bring H and g into BalNormalEquations' order
  // (point j at 3j, camera i at 3·np + 9i).
  const int np = p.num_points();
  std::vector<int> to(ne.dim());
  for (int b = 0; b < ne.num_free_variables(); ++b) {
    const Key k = ba.values.key(ne.free_variable(b));
    const int start = ne.hessian().block_start(b);
    const int target = is_bal_point_key(k) ? 3 * static_cast<int>(symbol_index(k))
                                           : 3 * np + 9 * static_cast<int>(symbol_index(k));
    for (int a = 0; a < ne.hessian().block_dim(b); ++a) to[start + a] = target + a;
  }
  const Eigen::MatrixXd H = ne.hessian().to_dense();
  r.H.resize(H.rows(), H.cols());
  r.g.resize(H.rows());
  for (int a = 0; a < H.rows(); ++a) {
    r.g[to[a]] = ne.gradient()[a];
    for (int b = 0; b < H.cols(); ++b) r.H(to[a], to[b]) = H(a, b);
  }
  return r;
}

TEST(BalNormalEquations, MatchTheFactorGraph) {
  BalProblem p = small_problem(6, 120);
  p.observations.push_back(p.observations[7]);  // a repeated (camera, point) pair shares its W block
  p.observations.back().pixel.x() += 0.7;
  for (const char* k : {"", "huber", "cauchy", "tukey"}) {
    std::shared_ptr<const RobustKernel> kernel = *k ? make_robust_kernel(k, 1.0) : nullptr;
    const Reference ref = generic_normal_equations(p, kernel);
    const ThreadPool pool(2);
    BalNormalEquations ne(p, kernel, pool);
    const BalState x = make_bal_state(p);
    const double cost = ne.linearize(x);
    const Eigen::MatrixXd H = ne.hessian().to_dense();
    ASSERT_EQ(H.rows(), ref.H.rows());
    EXPECT_NEAR(cost, ref.cost, 1e-10 * ref.cost) << k;
    EXPECT_NEAR(ne.cost(x), ref.cost, 1e-10 * ref.cost) << k;
    EXPECT_LT((H - ref.H).norm(), 1e-10 * ref.H.norm()) << k;
    EXPECT_LT((ne.gradient() - ref.g).norm(), 1e-10 * ref.g.norm()) << k;
    EXPECT_LT((ne.hessian_diagonal() - ref.H.diagonal()).norm(), 1e-10 * ref.H.norm()) << k;

    // δᵀHδ from the blocks, with and without damping on the diagonal.
    const Eigen::VectorXd d = Eigen::VectorXd::Random(H.rows());
    const double q = d.dot(ref.H * d);
    EXPECT_NEAR(ne.quadratic(d), q, 1e-9 * std::abs(q)) << k;
    ne.set_diagonal_damping(Eigen::VectorXd::Constant(H.rows(), 3.0));
    EXPECT_NEAR(ne.hessian().to_dense()(0, 0), ref.H(0, 0) + 3.0, 1e-9 * ref.H(0, 0));
    EXPECT_NEAR(ne.quadratic(d), q, 1e-9 * std::abs(q)) << k;
    ne.clear_damping();
    EXPECT_LT((ne.hessian().to_dense() - ref.H).norm(), 1e-10 * ref.H.norm()) << k;
  }
}

// The point pass on four lanes gives the bits of the eight-lane pass (where the CPU has AVX-512;
// elsewhere both runs take four lanes): H, g, diag(H) and the cost, with a repeated pair.
TEST(BalNormalEquations, FourAndEightLanesGiveTheSameBits) {
  BalProblem p = small_problem(6, 300, 5);
  p.observations.push_back(p.observations[11]);
  p.observations.back().pixel.y() -= 0.4;
  for (auto kernel : {std::shared_ptr<const RobustKernel>(), make_robust_kernel("cauchy", 1.0)}) {
    const ThreadPool pool(2);
    const BalState x = make_bal_state(p);
    BalNormalEquations wide(p, kernel, pool), narrow(p, kernel, pool);
    const double c_wide = wide.linearize(x);
    bal_point_pass_allow_eight_lanes(false);
    const double c_narrow = narrow.linearize(x);
    bal_point_pass_allow_eight_lanes(true);
    EXPECT_EQ(c_wide, c_narrow);
    EXPECT_EQ(wide.hessian().to_dense(), narrow.hessian().to_dense());
    EXPECT_EQ(wide.gradient(), narrow.gradient());
    EXPECT_EQ(wide.hessian_diagonal(), narrow.hessian_diagonal());
  }
}

// retract_and_linearize (the points' step by a back-substitution per chunk, inside the point
// pass) gives the bits of retract then linearize: H, g, diag(H), the cost and the candidate,
// squared and Huber loss, 1 and 3 threads; the callback sees every point exactly once.
TEST(BalNormalEquations, RetractAndLinearizeMatchesTheStepsApart) {
  const BalProblem p = small_problem(6, 700, 9);
  const BalState x = make_bal_state(p);
  for (auto kernel : {std::shared_ptr<const RobustKernel>(), make_robust_kernel("huber", 1.0)}) {
    for (int threads : {1, 3}) {
      const ThreadPool pool(threads);
      BalNormalEquations apart(p, kernel, pool), fused(p, kernel, pool);
      const int np = p.num_points();
      Eigen::VectorXd d = 1e-3 * Eigen::VectorXd::Random(apart.dim());
      BalState y_apart, y_fused;
      apart.retract(x, d.data(), y_apart);
      const double c_apart = apart.linearize(y_apart);
      Eigen::VectorXd d_fused = d;
      d_fused.head(3 * np).setConstant(std::nan(""));  // the points' rows come from the callback
      std::vector<int> seen(np, 0);
      const double c_fused = fused.retract_and_linearize(x, d_fused.data(), y_fused, [&](int b, int e, double* s) {
        for (int j = b; j < e; ++j) {
          ++seen[j];
          for (int a = 0; a < 3; ++a) s[3 * j + a] = d[3 * j + a];
        }
      });
      EXPECT_EQ(c_apart, c_fused);
      EXPECT_EQ(d, d_fused);
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), np);
      EXPECT_EQ(apart.hessian().values(), fused.hessian().values());
      EXPECT_EQ(apart.gradient(), fused.gradient());
      EXPECT_EQ(apart.hessian_diagonal(), fused.hessian_diagonal());
      EXPECT_EQ(y_apart.points, y_fused.points);
      for (int i = 0; i < p.num_cameras(); ++i)
        EXPECT_EQ(y_apart.cameras[i].to_bal(), y_fused.cameras[i].to_bal());
    }
  }
}

TEST(BalNormalEquations, RetractMatchesBalCameraPlus) {
  const BalProblem p = small_problem(3, 20);
  const ThreadPool pool(2);
  BalNormalEquations ne(p, nullptr, pool);
  const BalState x = make_bal_state(p);
  const Eigen::VectorXd d = 1e-2 * Eigen::VectorXd::Random(ne.dim());
  BalState y;
  ne.retract(x, d.data(), y);
  EXPECT_EQ(y.points[4], Eigen::Vector3d(x.points[4] + d.segment<3>(12)));
  const BalCamera c = x.cameras[2].plus(d.segment<9>(3 * p.num_points() + 18));
  EXPECT_EQ((c.to_bal() - y.cameras[2].to_bal()).norm(), 0.0);
}

TEST(BalLevenbergMarquardt, MatchesTheOptimizerOnTheFactorGraph) {
  const BalProblem start = small_problem(10, 400, 3);
  for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
    for (bool robust : {false, true}) {
      BundleAdjustmentResult r[2];
      for (int graph = 0; graph < 2; ++graph) {
        BalProblem p = start;
        BundleAdjustmentOptions o;
        o.use_factor_graph = graph == 1;
        o.optimizer.schur.method = m;
        if (robust) o.kernel = make_robust_kernel("huber", 1.0);
        r[graph] = optimize_bundle_adjustment(p, o);
        EXPECT_TRUE(r[graph].summary.success()) << r[graph].summary.message;
        EXPECT_NEAR(r[graph].final_cost, robust ? r[graph].final_cost : bal_cost(p), 1e-9 * r[graph].final_cost);
      }
      const std::string what = std::string(to_string(m)) + (robust ? " huber" : "");
      EXPECT_NEAR(r[0].initial_cost, r[1].initial_cost, 1e-10 * r[1].initial_cost) << what;
      EXPECT_NEAR(r[0].final_cost, r[1].final_cost, 1e-7 * r[1].final_cost) << what;
      EXPECT_NEAR(r[0].summary.iterations, r[1].summary.iterations, 1) << what;
      EXPECT_EQ(r[0].summary.linear_solver, r[1].summary.linear_solver) << what;
    }
  }
}

TEST(BalLevenbergMarquardt, BitIdenticalForAnyThreadCount) {
  const BalProblem start = small_problem(12, 900, 4);
  for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
    std::vector<std::string> out;
    for (int threads : {1, 2, 3}) {
      BalProblem p = start;
      BundleAdjustmentOptions o;
      o.optimizer.num_threads = threads;
      o.optimizer.schur.method = m;
      o.kernel = make_robust_kernel("cauchy", 2.0);
      const BundleAdjustmentResult r = optimize_bundle_adjustment(p, o);
      EXPECT_TRUE(r.summary.success()) << r.summary.message;
      out.push_back(bal_to_string(p));
    }
    EXPECT_EQ(out[0], out[1]) << to_string(m);
    EXPECT_EQ(out[0], out[2]) << to_string(m);
  }
}

TEST(BalLevenbergMarquardt, NonFiniteStartIsReported) {
  BalProblem p = small_problem(3, 20);
  p.points[5].x() = std::numeric_limits<double>::quiet_NaN();
  BundleAdjustmentOptions o;
  const BundleAdjustmentResult r = optimize_bundle_adjustment(p, o);
  EXPECT_EQ(r.summary.termination, Termination::kNonFiniteCost);
  EXPECT_NE(r.summary.message.find("observation"), std::string::npos) << r.summary.message;
}

}  // namespace
}  // namespace slamkit
