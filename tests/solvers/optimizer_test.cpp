#include "slamkit/solvers/optimizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/pose_graph_problem.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/sim/pose_graph_generator.h"
#include "slamkit/solvers/pose_graph_init.h"

namespace slamkit {
namespace {

using Vec1 = Eigen::Matrix<double, 1, 1>;

PoseGraph sim_graph(const std::string& world, double noise_scale = 1.0) {
  PoseGraphSimOptions o;
  o.world = world;
  o.num_poses = 400;
  o.rings = 8;
  o.poses_per_ring = 12;
  o.translation_sigma *= noise_scale;
  o.rotation_sigma *= noise_scale;
  return generate_pose_graph(o);
}

class AlgorithmsAgree : public ::testing::TestWithParam<std::string> {};

TEST_P(AlgorithmsAgree, SameOptimumFromTheSameStart) {
  PoseGraph g = sim_graph(GetParam());
  initialize_pose_graph(g, InitMethod::kAuto, gauge_vertices(g));
  std::vector<double> finals;
  for (Algorithm a : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM,
                      Algorithm::kDogleg}) {
    PoseGraphProblem p = build_pose_graph_problem(g);
    OptimizerOptions o;
    o.algorithm = a;
    o.function_tolerance = 1e-12;
    o.max_iterations = 200;
    const Summary s = Optimizer(o).optimize(p.graph, p.values);
    EXPECT_TRUE(s.success()) << to_string(a) << ": " << s.message;
    EXPECT_LT(s.final_cost, s.initial_cost);
    finals.push_back(s.final_cost);
  }
  for (double f : finals) EXPECT_NEAR(f, finals[0], 1e-6 * finals[0]);
}

INSTANTIATE_TEST_SUITE_P(Worlds, AlgorithmsAgree, ::testing::Values("manhattan", "sphere"));

TEST(Optimizer, ResultIsBitIdenticalForAnyThreadCount) {
  PoseGraph g = sim_graph("sphere");
  PoseGraphProblem a = build_pose_graph_problem(g), b = build_pose_graph_problem(g);
  OptimizerOptions o;
  o.algorithm = Algorithm::kGaussNewton;
  o.num_threads = 1;
  const Summary sa = Optimizer(o).optimize(a.graph, a.values);
  o.num_threads = 3;
  const Summary sb = Optimizer(o).optimize(b.graph, b.values);
  EXPECT_EQ(sa.final_cost, sb.final_cost);
  EXPECT_EQ(sa.iterations, sb.iterations);
  EXPECT_EQ(0, std::memcmp(a.values.parameter_data().data(), b.values.parameter_data().data(),
                           sizeof(double) * a.values.parameter_data().size()));
}

// r(x) = atan(x): Newton/Gauss-Newton diverges from |x0| > 1.39 (the step overshoots and grows).
struct Atan final : FactorN<1, Vec1> {
  using FactorN::FactorN;
  Residual error(const Vec1& x, Jacobian<Vec1>* J) const override {
    if (J) (*J)(0, 0) = 1.0 / (1.0 + x(0) * x(0));
    return Residual(std::atan(x(0)));
  }
};

TEST(Optimizer, GaussNewtonSafeguardFallsBackToLM) {
  FactorGraph g;
  g.emplace<Atan>(std::array<Key, 1>{1}, nullptr);
  Values v;
  v.insert(Key{1}, Vec1(2.0));
  OptimizerOptions o;
  o.algorithm = Algorithm::kGaussNewton;
  const Summary s = Optimizer(o).optimize(g, v);
  EXPECT_GT(s.fallback_iteration, 0) << s.report();
  EXPECT_LT(std::abs(v.at<Vec1>(1)(0)), 1e-4) << s.report();
  // Pure Gauss-Newton (no safeguard) never returns worse than its best iterate either.
  Values w;
  w.insert(Key{1}, Vec1(2.0));
  o.gn_patience = 0;
  o.max_iterations = 6;
  const Summary pure = Optimizer(o).optimize(g, w);
  EXPECT_LE(pure.final_cost, pure.initial_cost);
}

// r(x) = x − 3, but NaN beyond x > 1.5: steps into the NaN region must be rejected, never taken.
struct NanBeyond final : FactorN<1, Vec1> {
  using FactorN::FactorN;
  Residual error(const Vec1& x, Jacobian<Vec1>* J) const override {
    if (J) (*J)(0, 0) = 1.0;
    return Residual(x(0) > 1.5 ? std::nan("") : x(0) - 3.0);
  }
};

TEST(Optimizer, NonFiniteStepsAreRejectedNotTaken) {
  for (Algorithm a : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM,
                      Algorithm::kDogleg}) {
    FactorGraph g;
    g.emplace<NanBeyond>(std::array<Key, 1>{1}, nullptr);
    Values v;
    v.insert(Key{1}, Vec1(0.0));
    OptimizerOptions o;
    o.algorithm = a;
    o.max_iterations = 60;
    const Summary s = Optimizer(o).optimize(g, v);
    EXPECT_TRUE(std::isfinite(s.final_cost)) << to_string(a);
    EXPECT_LE(v.at<Vec1>(1)(0), 1.5) << to_string(a);
    EXPECT_LE(s.final_cost, s.initial_cost) << to_string(a);
  }
}

TEST(Optimizer, NonFiniteInitialCostIsReportedAndValuesUntouched) {
  FactorGraph g;
  g.emplace<NanBeyond>(std::array<Key, 1>{1}, nullptr);
  Values v;
  v.insert(Key{1}, Vec1(2.0));
  const Summary s = Optimizer().optimize(g, v);
  EXPECT_EQ(s.termination, Termination::kNonFiniteCost);
  EXPECT_FALSE(s.success());
  EXPECT_EQ(v.at<Vec1>(1)(0), 2.0);
  EXPECT_NE(s.message.find("factor 0"), std::string::npos);
}

TEST(Optimizer, RankDeficientSystemIsDampedNotFatal) {
  // No variable fixed: the pose graph has a free gauge, H is singular.
  PoseGraph g = sim_graph("manhattan");
  PoseGraphProblem p = build_pose_graph_problem(g);
  for (std::int64_t id : p.gauge) p.values.set_fixed(vertex_key(id), false);
  for (Algorithm a : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt, Algorithm::kDogleg,
                      Algorithm::kTrustRegionLM}) {
    Values v = p.values;
    OptimizerOptions o;
    o.algorithm = a;
    const Summary s = Optimizer(o).optimize(p.graph, v);
    EXPECT_TRUE(std::isfinite(s.final_cost)) << to_string(a);
    EXPECT_LT(s.final_cost, s.initial_cost) << to_string(a) << " " << s.message;
  }
}

TEST(Optimizer, SummaryJsonHasTheDocumentedKeys) {
  PoseGraph g = sim_graph("manhattan");
  PoseGraphProblem p = build_pose_graph_problem(g);
  const Summary s = Optimizer().optimize(p.graph, p.values);
  const auto j = nlohmann::json::parse(s.to_json());
  for (const char* key : {"initial_chi2", "final_chi2", "iterations", "linear_solves", "time_total_s",
                          "time_linear_solver_s", "solver", "linear_solver", "threads", "termination", "trace"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["trace"].size(), static_cast<std::size_t>(s.iterations + 1));
  EXPECT_NE(s.report().find("termination"), std::string::npos);
}

TEST(Optimizer, StopsOnTheRequestedCriterion) {
  PoseGraph g = sim_graph("sphere");
  PoseGraphProblem p = build_pose_graph_problem(g);
  OptimizerOptions o;
  o.max_iterations = 1;
  Values v = p.values;
  EXPECT_EQ(Optimizer(o).optimize(p.graph, v).termination, Termination::kMaxIterations);
  o.max_iterations = 100;
  o.gradient_tolerance = 1e30;
  v = p.values;
  EXPECT_EQ(Optimizer(o).optimize(p.graph, v).termination, Termination::kGradientTolerance);
  o.gradient_tolerance = 1e-10;
  o.callback = [](const IterationSummary& it) { return it.iteration < 2; };
  v = p.values;
  const Summary s = Optimizer(o).optimize(p.graph, v);
  EXPECT_EQ(s.termination, Termination::kUserCallback);
  EXPECT_EQ(s.iterations, 2);
}

}  // namespace
}  // namespace slamkit
