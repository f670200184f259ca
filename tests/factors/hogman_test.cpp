// HOG-Man (batch and online) and the back-end comparison on small generated graphs whose
// answer is known (exact measurements: the true poses have chi2 0).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/eval/report.h"
#include "slamkit/factors/backend_comparison.h"
#include "slamkit/factors/hogman.h"
#include "slamkit/factors/pose_graph_optimizer.h"

namespace slamkit {
namespace {

// A 2D or 3D trajectory around a square block, three laps, loop closures to earlier laps;
// the estimates are the odometry composed from slightly wrong measurements' drift.
PoseGraph laps(int dim) {
  PoseGraph g;
  const int n = 120;
  for (int i = 0; i < n; ++i) {
    GraphVertex v;
    v.id = i;
    const double a = 2 * M_PI * (i % 40) / 40.0;
    if (dim == 2) {
      v.kind = VertexKind::kPose2;
      v.pose2 = SE2(8 * std::cos(a), 8 * std::sin(a), a + M_PI / 2);
    } else {
      v.kind = VertexKind::kPose3;
      v.pose3 = SE3(SO3::from_rpy(0.05 * std::sin(a), 0.02, a + M_PI / 2), Eigen::Vector3d(8 * std::cos(a), 8 * std::sin(a), 0.02 * i));
    }
    g.add_vertex(v);
  }
  auto edge = [&](int a, int b) {
    GraphEdge e;
    e.from = a;
    e.to = b;
    if (dim == 2) {
      e.kind = EdgeKind::kPose2Pose2;
      e.pose2 = g.vertex(a).pose2.between(g.vertex(b).pose2);
      e.information = 100 * Eigen::Matrix3d::Identity();
    } else {
      e.kind = EdgeKind::kPose3Pose3;
      e.pose3 = g.vertex(a).pose3.between(g.vertex(b).pose3);
      e.information = 100 * Eigen::Matrix<double, 6, 6>::Identity();
    }
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
  for (int i = 40; i < n; i += 5) edge(i - 40, i);
  // Drift: perturb every pose after the first by an accumulating rotation error.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int i = 1; i < n; ++i) {
    GraphVertex& v = g.vertex_at(i);
    if (dim == 2) v.pose2 = v.pose2.plus(Eigen::Vector3d(0.2 * noise(rng), 0.2 * noise(rng), 0.05 * noise(rng)));
    else {
      Eigen::Matrix<double, 6, 1> d;
      for (int k = 0; k < 6; ++k) d[k] = (k < 3 ? 0.2 : 0.03) * noise(rng);
      v.pose3 = v.pose3.plus(d);
    }
  }
  return g;
}

TEST(Hogman, BatchReachesTheKnownOptimum) {
  for (int dim : {2, 3}) {
    PoseGraph g = laps(dim);
    const double before = total_chi2(g);
    HogmanOptions o;
    o.group_size = 4;
    o.top_nodes = 8;
    const RelaxerSummary s = optimize_hogman(g, o);
    EXPECT_EQ(s.method, "hogman");
    EXPECT_TRUE(std::isfinite(s.final_chi2));
    EXPECT_LT(s.final_chi2, 1e-6 * before) << dim << "D\n" << s.report();
  }
}

TEST(Hogman, OnlineReducesChi2AndTimesEveryPose) {
  for (int dim : {2, 3}) {
    PoseGraph g = laps(dim);
    const double before = total_chi2(g);
    HogmanOptions o;
    o.group_size = 4;
    o.top_nodes = 8;
    const HogmanOnlineResult r = hogman_online(g, o);
    ASSERT_EQ(r.time_per_pose_s.size(), g.vertices().size());
    EXPECT_EQ(r.graph_size.back(), static_cast<int>(g.vertices().size()));
    EXPECT_GT(r.levels, 0);
    EXPECT_TRUE(std::isfinite(r.final_chi2));
    EXPECT_LT(r.final_chi2, before) << dim << "D";
  }
}

// A 2D trajectory of `laps` rounds with noisy measurements (so the optimum is not 0) and the
// estimates composed from the noisy odometry (the file's start, as in M3500b: rotation noise
// sigma_theta makes it far from the optimum).
PoseGraph noisy_laps(int laps, double sigma_theta, unsigned seed) {
  PoseGraph g;
  const int per_lap = 40, n = laps * per_lap;
  std::vector<SE2> truth;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * (i % per_lap) / per_lap;
    truth.emplace_back((8 + 0.3 * (i / per_lap)) * std::cos(a), (8 + 0.3 * (i / per_lap)) * std::sin(a), a + M_PI / 2);
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const double sigma_t = 0.05;
  auto edge = [&](int a, int b) {
    GraphEdge e;
    e.from = a;
    e.to = b;
    e.kind = EdgeKind::kPose2Pose2;
    e.pose2 = truth[a].between(truth[b]).plus(Eigen::Vector3d(sigma_t * noise(rng), sigma_t * noise(rng), sigma_theta * noise(rng)));
    e.information = Eigen::Vector3d(1 / (sigma_t * sigma_t), 1 / (sigma_t * sigma_t), 1 / (sigma_theta * sigma_theta)).asDiagonal();
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
  for (int i = per_lap; i < n; i += 3) edge(i - per_lap, i);
  SE2 x;
  for (int i = 0; i < n; ++i) {
    GraphVertex v;
    v.id = i;
    v.kind = VertexKind::kPose2;
    v.pose2 = x;
    g.add_vertex(v);
    if (i + 1 < n) x = x * g.edges[i].pose2;  // edges[i] is the odometry i -> i+1
  }
  return g;
}

// The reference optimum: LM from the LAGO start (what `slamkit optimize` does by default).
double lm_optimum_from_lago(PoseGraph g) {
  PoseGraphOptimizerOptions po;
  po.init = InitMethod::kAuto;
  po.optimizer.algorithm = Algorithm::kLevenbergMarquardt;
  po.optimizer.max_iterations = 100;
  return optimize_pose_graph(g, po).final_chi2;
}

// The online fine level alone only receives rigid group moves and local refinements; the final
// fine-level pass brings it to the batch optimum.
TEST(Hogman, OnlineFinalPassTracksTheBatchOptimum) {
  PoseGraph g = noisy_laps(4, 0.01, 5);
  const double optimum = lm_optimum_from_lago(g);
  HogmanOptions o;
  o.group_size = 4;
  o.top_nodes = 8;
  PoseGraph online = g;
  const HogmanOnlineResult r = hogman_online(online, o);
  EXPECT_LE(r.final_chi2, r.chi2_before_final_pass);
  EXPECT_GT(r.final_pass_time_s, 0.0);
  EXPECT_LE(r.final_chi2, 1.01 * optimum) << "before the final pass " << r.chi2_before_final_pass;
  EXPECT_NEAR(total_chi2(online), r.final_chi2, 1e-9 * r.final_chi2);
}

// From a start with large rotation drift, the hierarchy built on the raw odometry leaves the
// fine level where Gauss-Newton falls into a worse minimum; the default start (LAGO) of the
// fine level and the damped fine pass reach the optimum.
TEST(Hogman, BatchReachesTheOptimumFromLargeRotationDrift) {
  PoseGraph g = noisy_laps(4, 0.15, 11);
  const double optimum = lm_optimum_from_lago(g);
  HogmanOptions o;
  o.group_size = 4;
  o.top_nodes = 8;
  PoseGraph h = g;
  const RelaxerSummary s = optimize_hogman(h, o);
  EXPECT_LE(s.final_chi2, optimum * (1 + 1e-4)) << s.report();
}

TEST(Hogman, RefusesWhatTheRelaxersRefuse) {
  PoseGraph g = laps(2);
  g.edges[3].information.setZero();
  EXPECT_THROW(optimize_hogman(g), InputError);
  HogmanOptions bad;
  bad.group_size = 1;
  PoseGraph h = laps(2);
  EXPECT_THROW(optimize_hogman(h, bad), InputError);
}

TEST(Compare, EveryBackEndFromTheSameStartRankedAndReadByTheReport) {
  PoseGraph g = laps(2);
  ComparisonOptions o;
  o.init = "none";
  o.time_budget_s = 2.0;
  o.max_iterations = 50;
  o.progress = false;
  const Comparison c = compare_backends(g, o);
  ASSERT_EQ(c.runs.size(), 9u);
  for (const BackendRun& r : c.runs) {
    EXPECT_TRUE(r.error.empty()) << r.solver << ": " << r.error;
    EXPECT_DOUBLE_EQ(r.initial_chi2, c.start_chi2) << r.solver;
    EXPECT_LE(r.final_chi2, r.initial_chi2) << r.solver;
    ASSERT_FALSE(r.trace.empty());
  }
  EXPECT_LT(c.runs.front().final_chi2, 1e-6 * c.start_chi2);  // the winner solved it
  // The report takes the comparison's JSON shape.
  nlohmann::json j = {{"kind", "compare"}, {"file", "laps"}, {"init", "none"}, {"runs", nlohmann::json::array()}};
  for (const BackendRun& r : c.runs) {
    nlohmann::json t = nlohmann::json::array();
    for (const auto& [time, chi2] : r.trace) t.push_back({time, chi2});
    j["runs"].push_back({{"solver", r.solver}, {"final_chi2", r.final_chi2}, {"time_total_s", r.time_total_s},
                         {"iterations", r.iterations}, {"trace", t}});
  }
  const auto runs = compare_runs_from_json(j, "c.json");
  ASSERT_EQ(runs.size(), 9u);
  const std::string html = render_html_report({{"c.json", j}}, {});
  EXPECT_NE(html.find("hogman"), std::string::npos);
  j["runs"][0]["trace"][0] = "bad";
  EXPECT_THROW(compare_runs_from_json(j, "c.json"), InputError);
}

TEST(Compare, UnknownBackEndAndBadBudgetAreRefused) {
  PoseGraph g = laps(2);
  ComparisonOptions o;
  o.solvers = {"gn", "nope"};
  EXPECT_THROW(compare_backends(g, o), InputError);
  o.solvers = {"gn"};
  o.time_budget_s = 0;
  EXPECT_THROW(compare_backends(g, o), InputError);
}

}  // namespace
}  // namespace slamkit
