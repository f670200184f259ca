// The pose-graph pipeline on graphs with special structure: several components, FIX
// vertices, landmarks (2D and 3D with a sensor offset).
#include "slamkit/factors/pose_graph_optimizer.h"

#include <gtest/gtest.h>

#include <random>

#include "slamkit/core/pose_graph_error.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit {
namespace {

PoseGraph two_components() {
  PoseGraphSimOptions o;
  o.num_poses = 300;
  PoseGraph a = generate_pose_graph(o);
  o.seed = 2;
  const PoseGraph b = generate_pose_graph(o);
  for (GraphVertex v : b.vertices()) {
    v.id += 10000;
    a.add_vertex(v);
  }
  for (GraphEdge e : b.edges) {
    e.from += 10000, e.to += 10000;
    a.edges.push_back(e);
  }
  return a;
}

TEST(PoseGraphOptimizer, DisconnectedGraphGetsAGaugePerComponent) {
  PoseGraph g = two_components();
  ASSERT_EQ(count_connected_components(g), 2u);
  const PoseGraphResult r = optimize_pose_graph(g);
  EXPECT_TRUE(r.summary.success()) << r.summary.report();
  EXPECT_LT(r.final_chi2, r.chi2_after_init);
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes[0].find("2 disconnected components"), std::string::npos) << r.notes[0];
  EXPECT_EQ(r.summary.num_fixed, 2);
}

TEST(PoseGraphOptimizer, FixedVerticesStayPut) {
  PoseGraphSimOptions o;
  o.num_poses = 200;
  PoseGraph g = generate_pose_graph(o);
  g.fixed = {50, 120};
  const SE2 before50 = g.vertex(50).pose2, before120 = g.vertex(120).pose2;
  PoseGraphOptimizerOptions opt;
  opt.init = InitMethod::kNone;
  const PoseGraphResult r = optimize_pose_graph(g, opt);
  EXPECT_TRUE(r.notes.empty());
  EXPECT_TRUE(g.vertex(50).pose2.matrix().isApprox(before50.matrix(), 0.0));
  EXPECT_TRUE(g.vertex(120).pose2.matrix().isApprox(before120.matrix(), 0.0));
  EXPECT_LT(r.final_chi2, r.input_chi2);
}

// init = auto keeps estimates that already fit the measurements: an optimized graph whose noise
// is stated 2× too large (information / 4: the same minimizer, χ²/dof ≈ 1/4 there) starts from
// its estimates (no initialization) and stays at its minimum; the generator's odometry start (far
// above its degrees of freedom) is initialized, and keep_estimates_chi2_per_dof = 0 always is.
TEST(PoseGraphOptimizer, AutoInitKeepsEstimatesThatFitTheNoise) {
  PoseGraphSimOptions o;
  o.num_poses = 400;
  PoseGraph g = generate_pose_graph(o);
  const PoseGraphResult first = optimize_pose_graph(g);
  EXPECT_EQ(first.init.used, InitMethod::kLinear);
  ASSERT_TRUE(first.summary.success());
  for (GraphEdge& e : g.edges) e.information *= 0.25;
  const PoseGraph optimized = g;
  const PoseGraphResult again = optimize_pose_graph(g);
  EXPECT_EQ(again.init.requested, InitMethod::kAuto);
  EXPECT_EQ(again.init.used, InitMethod::kNone);
  ASSERT_FALSE(again.notes.empty());
  EXPECT_NE(again.notes[0].find("estimates fit its measurements"), std::string::npos) << again.notes[0];
  EXPECT_EQ(again.chi2_after_init, again.input_chi2);
  EXPECT_NEAR(again.final_chi2, 0.25 * first.final_chi2, 1e-9 * first.final_chi2);
  PoseGraph forced = optimized;
  PoseGraphOptimizerOptions always;
  always.keep_estimates_chi2_per_dof = 0.0;
  const PoseGraphResult initialized = optimize_pose_graph(forced, always);
  EXPECT_EQ(initialized.init.used, InitMethod::kLinear);
  EXPECT_NEAR(initialized.final_chi2, again.final_chi2, 1e-9 * again.final_chi2);
}

// Poses on a circle observing landmarks, exact measurements, perturbed start: the optimum is
// the truth (chi2 = 0).
template <bool kThreeD>
PoseGraph landmark_graph(PoseGraph* truth) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.05);
  PoseGraph g;
  const SE3 offset(SO3::exp(Eigen::Vector3d(0.1, -0.2, 0.3)), Eigen::Vector3d(0.2, 0.0, 0.1));
  if (kThreeD) g.sensor_offsets[7] = offset;
  const int poses = 40, points = 15;
  for (int i = 0; i < poses; ++i) {
    GraphVertex v{i, kThreeD ? VertexKind::kPose3 : VertexKind::kPose2};
    const double a = 2 * kPi * i / poses;
    v.pose2 = SE2(5 * std::cos(a), 5 * std::sin(a), a + kPi / 2);
    v.pose3 = SE3(SO3::exp(Eigen::Vector3d(0, 0, a + kPi / 2)), Eigen::Vector3d(5 * std::cos(a), 5 * std::sin(a), 0.3 * std::sin(3 * a)));
    g.add_vertex(v);
  }
  for (int k = 0; k < points; ++k) {
    GraphVertex p{1000 + k, kThreeD ? VertexKind::kPoint3 : VertexKind::kPoint2};
    const double a = 2 * kPi * k / points;
    p.point = Eigen::Vector3d(8 * std::cos(a), 8 * std::sin(a), kThreeD ? 1.0 + 0.5 * std::cos(2 * a) : 0.0);
    g.add_vertex(p);
  }
  for (int i = 0; i < poses; ++i) {
    GraphEdge e;
    e.from = i, e.to = (i + 1) % poses;
    if (kThreeD) {
      e.kind = EdgeKind::kPose3Pose3;
      e.pose3 = g.vertex(e.from).pose3.between(g.vertex(e.to).pose3);
      e.information = 100.0 * Eigen::MatrixXd::Identity(6, 6);
    } else {
      e.kind = EdgeKind::kPose2Pose2;
      e.pose2 = g.vertex(e.from).pose2.between(g.vertex(e.to).pose2);
      e.information = 100.0 * Eigen::MatrixXd::Identity(3, 3);
    }
    g.edges.push_back(e);
    for (int k = 0; k < points; k += 1 + i % 3) {
      GraphEdge o;
      o.from = i, o.to = 1000 + k;
      if (kThreeD) {
        o.kind = EdgeKind::kPose3Point3, o.sensor_offset_id = 7;
        o.point = (g.vertex(i).pose3 * offset).inverse().act(g.vertex(o.to).point);
        o.information = 10.0 * Eigen::MatrixXd::Identity(3, 3);
      } else {
        o.kind = EdgeKind::kPose2Point2;
        o.point.head<2>() = g.vertex(i).pose2.inverse().act(g.vertex(o.to).point.head<2>());
        o.information = 10.0 * Eigen::MatrixXd::Identity(2, 2);
      }
      g.edges.push_back(o);
    }
  }
  *truth = g;
  for (std::size_t i = 1; i < g.vertices().size(); ++i) {  // perturb all but the gauge
    GraphVertex& v = g.vertex_at(i);
    v.pose2 = v.pose2.plus(SE2::Tangent(n(rng), n(rng), n(rng)));
    SE3::Tangent d;
    for (int c = 0; c < 6; ++c) d[c] = n(rng);
    v.pose3 = v.pose3.plus(d);
    v.point += Eigen::Vector3d(n(rng), n(rng), kThreeD ? n(rng) : 0.0);
  }
  return g;
}

TEST(PoseGraphOptimizer, LandmarkGraphsConvergeToTheTruth) {
  PoseGraph truth2, truth3;
  PoseGraph g2 = landmark_graph<false>(&truth2), g3 = landmark_graph<true>(&truth3);
  for (PoseGraph* g : {&g2, &g3}) {
    EXPECT_GT(total_chi2(*g), 1.0);
    PoseGraphOptimizerOptions o;
    o.init = InitMethod::kNone;
    o.optimizer.function_tolerance = 1e-12;
    const PoseGraphResult r = optimize_pose_graph(*g, o);
    EXPECT_TRUE(r.summary.success()) << r.summary.report();
    EXPECT_LT(r.final_chi2, 1e-12) << r.summary.report();
  }
  EXPECT_TRUE(g3.vertex(1003).point.isApprox(truth3.vertex(1003).point, 1e-6));
  // The chordal/linear initializers handle landmark graphs too (landmarks from their poses).
  PoseGraph again = landmark_graph<true>(&truth3);
  const PoseGraphResult r = optimize_pose_graph(again);
  EXPECT_LT(r.final_chi2, 1e-9);
}

}  // namespace
}  // namespace slamkit
