#include "slamkit/core/pose_graph.h"

#include <gtest/gtest.h>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit {
namespace {

GraphEdge pose2_edge(std::int64_t a, std::int64_t b, const SE2& z) {
  GraphEdge e;
  e.from = a, e.to = b, e.kind = EdgeKind::kPose2Pose2, e.pose2 = z;
  e.information = Eigen::Matrix3d::Identity();
  return e;
}

TEST(PoseGraph, RejectsDuplicateIdsAndMixedDimensions) {
  PoseGraph g;
  EXPECT_TRUE(g.add_vertex({1, VertexKind::kPose2}));
  EXPECT_FALSE(g.add_vertex({1, VertexKind::kPose3}));
  EXPECT_EQ(g.dimension(), 2);
  g.add_vertex({2, VertexKind::kPose3});
  EXPECT_THROW(g.dimension(), InputError);
  EXPECT_THROW(g.vertex(99), InputError);
}

TEST(PoseGraph, OdometryCompletionComposesChainThenBreadthFirst) {
  PoseGraph g;
  for (int i = 0; i < 5; ++i) {
    GraphVertex v{i, VertexKind::kPose2};
    v.has_estimate = false;
    g.add_vertex(v);
  }
  const SE2 step(1.0, 0.0, kPi / 2);
  for (int i = 0; i + 1 < 4; ++i) g.edges.push_back(pose2_edge(i, i + 1, step));
  g.edges.push_back(pose2_edge(4, 0, SE2(0.5, 0.5, 0.1)));  // vertex 4 only through a reversed edge
  EXPECT_EQ(complete_estimates_by_odometry(g), 5u);
  EXPECT_TRUE(g.vertex(3).pose2.matrix().isApprox((step * step * step).matrix(), 1e-12));
  EXPECT_TRUE(g.vertex(4).pose2.matrix().isApprox(SE2(0.5, 0.5, 0.1).inverse().matrix(), 1e-12));
  EXPECT_NEAR(total_chi2(g), 0.0, 1e-20);
  EXPECT_EQ(count_connected_components(g), 1u);
}

TEST(PoseGraph, CountsComponentsAndRootsEachOne) {
  PoseGraph g;
  for (int i = 0; i < 4; ++i) {
    GraphVertex v{i, VertexKind::kPose2};
    v.has_estimate = false;
    g.add_vertex(v);
  }
  g.edges.push_back(pose2_edge(0, 1, SE2(1, 0, 0)));
  g.edges.push_back(pose2_edge(2, 3, SE2(1, 0, 0)));
  EXPECT_EQ(count_connected_components(g), 2u);
  EXPECT_EQ(complete_estimates_by_odometry(g), 4u);
  EXPECT_TRUE(g.vertex(2).pose2.translation().isZero());
  EXPECT_NEAR(g.vertex(3).pose2.x(), 1.0, 1e-15);
}

TEST(PoseGraph, OdometryEdgesAreConsecutiveIds) {
  EXPECT_TRUE(is_odometry(pose2_edge(3, 4, SE2())));
  EXPECT_TRUE(is_odometry(pose2_edge(4, 3, SE2())));
  EXPECT_FALSE(is_odometry(pose2_edge(3, 9, SE2())));
}

}  // namespace
}  // namespace slamkit

namespace slamkit {
namespace {

TEST(PoseGraph, TrajectoryIsPosesInIdOrder) {
  PoseGraph g;
  GraphVertex a{5, VertexKind::kPose2}, b{2, VertexKind::kPose2}, p{9, VertexKind::kPoint2};
  a.pose2 = SE2(1, 2, 0.5);
  g.add_vertex(a);
  g.add_vertex(b);
  g.add_vertex(p);
  const Trajectory t = to_trajectory(g);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].stamp, 2.0);
  EXPECT_EQ(t[1].stamp, 5.0);
  EXPECT_TRUE(t[1].T_world_body.translation().isApprox(Eigen::Vector3d(1, 2, 0)));
  EXPECT_NEAR(t[1].T_world_body.rotation().log().z(), 0.5, 1e-15);
}

}  // namespace
}  // namespace slamkit
