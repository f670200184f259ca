// The relaxers (SGD, TORO, Gauss-Seidel relaxation, multi-level relaxation): each reduces chi2
// on small generated graphs whose answer is known, runs deterministically, and refuses graphs
// it cannot take with a clear message.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/solvers/relaxer_init.h"
#include "slamkit/solvers/sgd.h"
#include "slamkit/solvers/toro.h"
#include "testing/data.h"

namespace slamkit {
namespace {

const char* kMethods[] = {"sgd", "toro", "relax", "mlr"};

GraphEdge edge2(const PoseGraph& g, std::int64_t a, std::int64_t b, double info = 100.0) {
  GraphEdge e;
  e.from = a;
  e.to = b;
  e.kind = EdgeKind::kPose2Pose2;
  e.pose2 = g.vertex(a).pose2.between(g.vertex(b).pose2);
  e.information = info * Eigen::Matrix3d::Identity();
  return e;
}

GraphEdge edge3(const PoseGraph& g, std::int64_t a, std::int64_t b, double info = 100.0) {
  GraphEdge e;
  e.from = a;
  e.to = b;
  e.kind = EdgeKind::kPose3Pose3;
  e.pose3 = g.vertex(a).pose3.between(g.vertex(b).pose3);
  e.information = info * Eigen::Matrix<double, 6, 6>::Identity();
  return e;
}

// A square loop of poses driven twice around (so the second lap closes loops with the first),
// exact measurements: the true poses have chi2 0. The estimates are then perturbed.
PoseGraph loop_graph(int dim, bool loops = true, unsigned seed = 7) {
  PoseGraph g;
  const int n = 40;
  for (int i = 0; i < n; ++i) {
    GraphVertex v;
    v.id = i;
    const double a = 2 * M_PI * (i % 20) / 20.0;
    if (dim == 2) {
      v.kind = VertexKind::kPose2;
      v.pose2 = SE2(5 * std::cos(a), 5 * std::sin(a), a + M_PI / 2);
    } else {
      v.kind = VertexKind::kPose3;
      const double z = 0.1 * i;
      v.pose3 = SE3(SO3::from_rpy(0.1 * std::sin(a), 0.05, a + M_PI / 2), Eigen::Vector3d(5 * std::cos(a), 5 * std::sin(a), z));
    }
    g.add_vertex(v);
  }
  for (int i = 0; i + 1 < n; ++i) g.edges.push_back(dim == 2 ? edge2(g, i, i + 1) : edge3(g, i, i + 1));
  if (loops)
    for (int i = 20; i < n; i += 3) g.edges.push_back(dim == 2 ? edge2(g, i - 20, i) : edge3(g, i - 20, i));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t i = 1; i < g.vertices().size(); ++i) {
    GraphVertex& v = g.vertex_at(i);
    if (dim == 2) {
      v.pose2 = v.pose2.plus(Eigen::Vector3d(0.3 * noise(rng), 0.3 * noise(rng), 0.1 * noise(rng)));
    } else {
      Eigen::Matrix<double, 6, 1> d;
      for (int k = 0; k < 6; ++k) d[k] = (k < 3 ? 0.3 : 0.05) * noise(rng);
      v.pose3 = v.pose3.plus(d);
    }
  }
  return g;
}

RelaxerStop iterations(int n) {
  RelaxerStop s;
  s.max_iterations = n;
  return s;
}

class EachRelaxer : public ::testing::TestWithParam<const char*> {};

TEST_P(EachRelaxer, ReducesChi2TowardsTheKnownAnswer2D) {
  PoseGraph g = loop_graph(2);
  const double before = total_chi2(g);
  const RelaxerSummary s = run_named_relaxer(g, GetParam(), iterations(200));
  EXPECT_TRUE(std::isfinite(s.final_chi2));
  EXPECT_DOUBLE_EQ(s.final_chi2, total_chi2(g));
  EXPECT_LT(s.final_chi2, 0.05 * before) << GetParam() << ": " << s.report();
  EXPECT_EQ(s.trace.front().chi2, before);
  EXPECT_EQ(static_cast<int>(s.trace.size()), s.iterations + 1);
  // Pose 0 is the gauge: it never moves.
  EXPECT_EQ(g.vertex(0).pose2.x(), 5.0);
}

TEST_P(EachRelaxer, ReducesChi2TowardsTheKnownAnswer3D) {
  PoseGraph g = loop_graph(3);
  const double before = total_chi2(g);
  const RelaxerSummary s = run_named_relaxer(g, GetParam(), iterations(200));
  EXPECT_TRUE(std::isfinite(s.final_chi2));
  EXPECT_LT(s.final_chi2, 0.05 * before) << GetParam() << ": " << s.report();
}

TEST_P(EachRelaxer, DeterministicForAFixedSeed) {
  PoseGraph a = loop_graph(2), b = loop_graph(2);
  run_named_relaxer(a, GetParam(), iterations(20));
  run_named_relaxer(b, GetParam(), iterations(20));
  for (std::size_t i = 0; i < a.vertices().size(); ++i) {
    EXPECT_EQ(a.vertices()[i].pose2.x(), b.vertices()[i].pose2.x());
    EXPECT_EQ(a.vertices()[i].pose2.theta(), b.vertices()[i].pose2.theta());
  }
}

TEST_P(EachRelaxer, NoLoopClosureIsSolvedExactlyWithoutNaN) {
  for (int dim : {2, 3}) {
    PoseGraph g = loop_graph(dim, /*loops=*/false);
    const RelaxerSummary s = run_named_relaxer(g, GetParam(), iterations(300));
    EXPECT_EQ(s.num_loop_closures, 0);
    EXPECT_TRUE(std::isfinite(s.final_chi2));
    EXPECT_LT(s.final_chi2, 1e-3 * s.initial_chi2) << GetParam() << " " << dim << "D";
  }
}

TEST_P(EachRelaxer, DisconnectedGraphIsRefusedClearly) {
  PoseGraph g = loop_graph(2);
  GraphVertex v;
  v.id = 100;
  g.add_vertex(v);
  GraphVertex w;
  w.id = 101;
  g.add_vertex(w);
  g.edges.push_back(edge2(g, 100, 101));
  try {
    run_named_relaxer(g, GetParam(), iterations(5));
    FAIL() << "accepted a disconnected graph";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("connected components"), std::string::npos) << e.what();
  }
}

TEST_P(EachRelaxer, SingularInformationIsRefusedClearly) {
  PoseGraph g = loop_graph(2);
  g.edges[5].information(2, 2) = 0.0;
  g.edges[5].line = 17;
  try {
    run_named_relaxer(g, GetParam(), iterations(5));
    FAIL() << "accepted a singular information matrix";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 17);
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Relaxers, EachRelaxer, ::testing::ValuesIn(kMethods));

TEST(Sgd, ShuffleDependsOnTheSeedOnly) {
  PoseGraph a = loop_graph(2), b = loop_graph(2);
  SgdOptions o;
  o.stop = iterations(o.file_order_iterations + 3);  // the random order starts after the file-order ones
  o.seed = 1;
  optimize_sgd(a, o);
  o.seed = 2;
  optimize_sgd(b, o);
  EXPECT_NE(total_chi2(a), total_chi2(b));
}

TEST(Sgd, ConvergesFromAllZeroPoses2D) {
  PoseGraph g = loop_graph(2);
  for (std::size_t i = 0; i < g.vertices().size(); ++i) g.vertex_at(i).pose2 = SE2();
  const double before = total_chi2(g);
  const RelaxerSummary s = run_named_relaxer(g, "sgd", iterations(300));
  EXPECT_LT(s.final_chi2, 1e-3 * before) << s.report();
}

// A non-monotone method (SGD, TORO) ends with the best iterate it visited, not the last one:
// here a scripted "method" that first halves the perturbation of pose 5, then doubles it twice.
TEST(RunRelaxer, ReturnsTheBestIterateOfANonMonotoneMethod) {
  PoseGraph g = loop_graph(2, true, 3);
  const SE2 truth = loop_graph(2, true, 3).vertex(5).pose2;  // same perturbation; pose 5 moved below
  GraphVertex& v = g.vertex_at(*g.index_of(5));
  v.pose2 = truth.plus(Eigen::Vector3d(1.0, 0.0, 0.0));
  double offset = 1.0;
  auto step = [&](int k) {
    offset = k == 1 ? offset * 0.25 : offset * 4.0;
    g.vertex_at(*g.index_of(5)).pose2 = truth.plus(Eigen::Vector3d(offset, 0.0, 0.0));
    return offset;
  };
  RelaxerStop stop = iterations(3);
  stop.relative_tolerance = 0;
  const RelaxerSummary s = run_relaxer(g, "scripted", stop, step, [] {});
  ASSERT_EQ(s.trace.size(), 4u);
  double best = s.trace[0].chi2;
  for (const RelaxerIteration& it : s.trace) best = std::min(best, it.chi2);
  EXPECT_LT(best, s.trace.back().chi2);
  EXPECT_DOUBLE_EQ(s.final_chi2, best);
  EXPECT_DOUBLE_EQ(total_chi2(g), best);  // the graph holds the best iterate
  EXPECT_NEAR(g.vertex(5).pose2.x(), truth.plus(Eigen::Vector3d(0.25, 0.0, 0.0)).x(), 1e-12);
}

TEST(RelaxerGraph, LandmarksAreRefused) {
  PoseGraph g = loop_graph(2);
  GraphVertex p;
  p.id = 500;
  p.kind = VertexKind::kPoint2;
  g.add_vertex(p);
  EXPECT_THROW(run_named_relaxer(g, "toro", iterations(1)), InputError);
}

TEST(RelaxerInit, HandsItsResultToTheManifoldSolver) {
  PoseGraph g = loop_graph(2);
  const double before = total_chi2(g);
  const InitSummary s = initialize_pose_graph(g, parse_init_method("toro"), {0});
  EXPECT_EQ(s.used, InitMethod::kToro);
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes[0].find("toro: chi2"), std::string::npos);
  EXPECT_LT(total_chi2(g), before);
}

// MIT Killian Court: LM from the odometry guess ends in a bad local minimum (g2o: 21600);
// from the SGD or TORO result it reaches the optimum.
TEST(RelaxerDatasets, SgdAndToroLeadLmToTheOptimumOfMitb) {
  SLAMKIT_REQUIRE_DATA(file, "posegraph/2d/input_MITb_g2o.g2o");
  for (const char* init : {"sgd", "toro"}) {
    PoseGraph g = read_pose_graph(file.string());
    PoseGraphOptimizerOptions o;
    o.init = parse_init_method(init);
    o.optimizer.algorithm = Algorithm::kLevenbergMarquardt;
    o.optimizer.num_threads = 1;
    const PoseGraphResult r = optimize_pose_graph(g, o);
    EXPECT_LT(r.chi2_after_init, 0.01 * r.input_chi2) << init;
    EXPECT_LE(r.final_chi2, 41.1633 * (1 + 1e-4)) << init;
  }
}

// M3500b (M3500 with extra rotational noise): LM from odometry ends in a bad local minimum
// (g2o: 34975). SGD's first iterations in file order put it into the optimum's basin (from the
// random order LM ended at 24169).
TEST(RelaxerDatasets, SgdLeadsLmIntoTheOptimumsBasinOnM3500b) {
  SLAMKIT_REQUIRE_DATA(file, "posegraph/2d/input_M3500b_g2o.g2o");
  PoseGraph g = read_pose_graph(file.string());
  PoseGraphOptimizerOptions o;
  o.init = InitMethod::kSgd;
  o.optimizer.algorithm = Algorithm::kLevenbergMarquardt;
  o.optimizer.num_threads = 1;
  const PoseGraphResult r = optimize_pose_graph(g, o);
  EXPECT_LE(r.final_chi2, 4511.08) << r.summary.report();
}

}  // namespace
}  // namespace slamkit

namespace slamkit {
namespace {

// Noisy measurements: the optimum has chi2 > 0. The papers' update (the path-length factor,
// no θ–translation coupling) stops above it; the gradient phase (relaxer.h) has the
// least-squares optimum as its fixed point, found here by Gauss-Newton.
PoseGraph noisy_loop_graph() {
  PoseGraph g = loop_graph(2, true, 11);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (GraphEdge& e : g.edges) e.pose2 = e.pose2.plus(Eigen::Vector3d(0.05 * noise(rng), 0.05 * noise(rng), 0.02 * noise(rng)));
  return g;
}

TEST(GradientPhase, SgdAndToroReachTheLeastSquaresOptimum) {
  PoseGraph opt = noisy_loop_graph();
  PoseGraphOptimizerOptions lm;
  lm.optimizer.algorithm = Algorithm::kGaussNewton;
  lm.optimizer.num_threads = 1;
  const double best = optimize_pose_graph(opt, lm).final_chi2;
  ASSERT_GT(best, 1.0);
  for (const bool phase : {false, true}) {
    PoseGraph a = noisy_loop_graph(), b = noisy_loop_graph();
    SgdOptions so;
    ToroOptions to;
    so.stop = to.stop = iterations(400);
    so.stop.relative_tolerance = to.stop.relative_tolerance = 0;
    if (!phase) so.gradient_phase.start = to.gradient_phase.start = -1;
    const double sgd = optimize_sgd(a, so).final_chi2, toro = optimize_toro(b, to).final_chi2;
    // Measured: off 10.9 / 9.6 (the biased fixed point, 5× the optimum 2.009), on 2.46 / 2.14
    // after 400 iterations (2.23 / 2.11 after 4000: the 1/t learning rate converges slowly).
    if (phase) {
      EXPECT_LT(sgd, 1.3 * best) << "optimum " << best;
      EXPECT_LT(toro, 1.3 * best) << "optimum " << best;
    } else {
      EXPECT_GT(sgd, 3 * best) << "optimum " << best;
      EXPECT_GT(toro, 3 * best) << "optimum " << best;
    }
    std::printf("gradient phase %s: sgd %.6g, toro %.6g, optimum %.6g\n", phase ? "on" : "off", sgd, toro, best);
  }
}

}  // namespace
}  // namespace slamkit
