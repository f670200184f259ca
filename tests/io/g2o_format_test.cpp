// g2o reader/writer: every vertex and edge kind, bit-identical round trips, strictness.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "graph_compare.h"
#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"

namespace slamkit {
namespace {

using testing::read_text;
using testing::same_graph;

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// A 2D graph with every 2D kind, numbers at full precision, angles outside (−π, π].
std::string random_2d_text(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::string s = "# 2D graph\n";
  for (int i = 0; i < 6; ++i) s += "VERTEX_SE2 " + std::to_string(i) + " " + num(u(rng)) + " " + num(u(rng)) + " " + num(u(rng)) + "\n";
  for (int i = 6; i < 9; ++i) s += "VERTEX_XY " + std::to_string(i) + " " + num(u(rng)) + " " + num(u(rng)) + "\n";
  s += "FIX 0\n";
  for (int i = 0; i < 6; ++i) {
    s += "EDGE_SE2 " + std::to_string(i) + " " + std::to_string((i + 1) % 6) + " " + num(u(rng)) + " " + num(u(rng)) + " " +
         num(u(rng)) + " " + num(500 + u(rng)) + " " + num(u(rng)) + " " + num(u(rng)) + " " + num(500 + u(rng)) + " " +
         num(u(rng)) + " " + num(900 + u(rng)) + "\n";
  }
  for (int i = 6; i < 9; ++i) {
    s += "EDGE_SE2_XY " + std::to_string(i - 6) + " " + std::to_string(i) + " " + num(u(rng)) + " " + num(u(rng)) + " " +
         num(50 + u(rng)) + " " + num(u(rng)) + " " + num(50 + u(rng)) + "\n";
  }
  return s;
}

std::string quaternion_text(std::mt19937& rng, int digits) {
  std::normal_distribution<double> n;
  Eigen::Vector4d q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  std::string s;
  for (int k = 0; k < 4; ++k) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), " %.*g", digits, q[k]);
    s += buf;
  }
  return s;
}

// A 3D graph with every 3D kind; quaternions printed with 7 digits (not unit to 1e-16).
std::string random_3d_text(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::string s;
  s += "PARAMS_SE3OFFSET 0 0 0 0 0 0 0 1\n";
  s += "PARAMS_SE3OFFSET 3 " + num(u(rng)) + " " + num(u(rng)) + " " + num(u(rng)) + quaternion_text(rng, 7) + "\n";
  for (int i = 0; i < 5; ++i)
    s += "VERTEX_SE3:QUAT " + std::to_string(i) + " " + num(u(rng)) + " " + num(u(rng)) + " " + num(u(rng)) + quaternion_text(rng, 7) + "\n";
  for (int i = 10; i < 13; ++i)
    s += "VERTEX_TRACKXYZ " + std::to_string(i) + " " + num(u(rng)) + " " + num(u(rng)) + " " + num(u(rng)) + "\n";
  s += "FIX 0 1\n";
  for (int i = 0; i < 5; ++i) {
    s += "EDGE_SE3:QUAT " + std::to_string(i) + " " + std::to_string((i + 1) % 5) + " " + num(u(rng)) + " " + num(u(rng)) +
         " " + num(u(rng)) + quaternion_text(rng, 17);
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c) s += " " + num(r == c ? 100 + u(rng) : u(rng));
    s += "\n";
  }
  for (int i = 10; i < 13; ++i) {
    s += "EDGE_SE3_TRACKXYZ " + std::to_string(i - 10) + " " + std::to_string(i) + (i == 10 ? " 0 " : " 3 ") + num(u(rng)) +
         " " + num(u(rng)) + " " + num(u(rng));
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) s += " " + num(r == c ? 100 + u(rng) : u(rng));
    s += "\n";
  }
  return s;
}

TEST(G2oFormat, ReadsEveryKindWithFullSymmetricInformation) {
  const PoseGraph g = read_text(
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 2 0.5\nVERTEX_XY 7 3 4\n"
      "EDGE_SE2 0 1 1 2 0.5 11 12 13 22 23 33\nEDGE_SE2_XY 1 7 0.25 -1 5 0.5 6\nFIX 0\n");
  ASSERT_EQ(g.vertices().size(), 3u);
  ASSERT_EQ(g.edges.size(), 2u);
  EXPECT_EQ(g.format, "g2o");
  EXPECT_EQ(g.vertex(7).kind, VertexKind::kPoint2);
  Eigen::Matrix3d want;
  want << 11, 12, 13, 12, 22, 23, 13, 23, 33;
  EXPECT_EQ(Eigen::Matrix3d(g.edges[0].information), want);
  Eigen::Matrix2d want2;
  want2 << 5, 0.5, 0.5, 6;
  EXPECT_EQ(Eigen::Matrix2d(g.edges[1].information), want2);
  EXPECT_EQ(g.fixed, std::vector<std::int64_t>{0});
  EXPECT_EQ(g.edges[1].line, 5);

  const PoseGraph g3 = read_text(
      "PARAMS_SE3OFFSET 2 1 0 0 0 0 0 1\nVERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_TRACKXYZ 1 3 0 0\n"
      "EDGE_SE3_TRACKXYZ 0 1 2 2 0 0 1 0 0 1 0 1\n");
  ASSERT_EQ(g3.sensor_offsets.count(2), 1u);
  EXPECT_EQ(g3.edges[0].sensor_offset_id, 2);
  EXPECT_NEAR(total_chi2(g3), 0.0, 1e-24);  // (X·O)⁻¹ p = 3 − 1 = 2 = z
}

TEST(G2oFormat, RoundTripIsBitIdenticalForEveryKind) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    for (const std::string& text : {random_2d_text(rng), random_3d_text(rng)}) {
      const PoseGraph a = read_text(text);
      const std::string written = pose_graph_to_string(a, PoseGraphFormat::kG2o);
      const PoseGraph b = read_text(written);
      ASSERT_TRUE(same_graph(a, b, 0.0, 0.0)) << text;
      EXPECT_EQ(pose_graph_to_string(b, PoseGraphFormat::kG2o), written);
      EXPECT_EQ(total_chi2(a), total_chi2(b));
    }
  }
}

TEST(G2oFormat, NormalizedQuaternionsAreFixedPointsOfTheReader) {
  // Writing the stored (normalized) quaternion and reading it again changes no bit, for
  // quaternions whose plain normalization q/‖q‖ is not idempotent in floating point.
  std::mt19937 rng(3);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const std::string text = "VERTEX_SE3:QUAT 0 0 0 0" + quaternion_text(rng, 17) + "\n";
    const PoseGraph a = read_text(text);
    const Eigen::Quaterniond& q = a.vertices()[0].pose3.rotation().quaternion();
    EXPECT_EQ(q.norm(), 1.0);
    const PoseGraph b = read_text(pose_graph_to_string(a, PoseGraphFormat::kG2o));
    ASSERT_TRUE(testing::same_pose3(a.vertices()[0].pose3, b.vertices()[0].pose3, 0.0));
    ++checked;
  }
  EXPECT_EQ(checked, 2000);
}

TEST(G2oFormat, ComposedEstimatesRoundTripBitIdentically) {
  // Edges-only 3D graph: the odometry completion composes quaternions, whose plain
  // normalization is not a fixed point of write → read (found by fuzzing).
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::string text;
  for (int i = 0; i < 40; ++i) {
    const int from = i == 39 ? 45 : i, to = i == 39 ? 1 : i + 1;  // the last one only backwards
    text += "EDGE_SE3:QUAT " + std::to_string(from) + " " + std::to_string(to) + " " + num(u(rng)) + " " + num(u(rng)) +
            " " + num(u(rng)) + quaternion_text(rng, 17) + " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";
  }
  const PoseGraph a = read_text(text);
  ASSERT_EQ(a.vertices().size(), 41u);
  const PoseGraph b = read_text(pose_graph_to_string(a, PoseGraphFormat::kG2o));
  EXPECT_TRUE(same_graph(a, b, 0.0, 0.0));
}

TEST(G2oFormat, WritesEdgesOnlyGraphsWithoutVertexLines) {
  PoseGraphReadOptions o;
  o.complete_estimates = false;
  PoseGraphReadReport report;
  const PoseGraph a = read_text("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n", "e.g2o", o, &report);
  EXPECT_TRUE(report.edges_only);
  EXPECT_EQ(report.completed_estimates, 0u);
  const std::string text = pose_graph_to_string(a, PoseGraphFormat::kG2o);
  EXPECT_EQ(text.find("VERTEX"), std::string::npos) << text;
  EXPECT_TRUE(same_graph(a, read_text(text, "e.g2o", o), 0.0, 0.0));
}

TEST(G2oFormat, FixReferencesMustExistAndAcceptSeveralIds) {
  const PoseGraph g = read_text("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nFIX 0 1\nFIX 1\n");
  EXPECT_EQ(g.fixed, (std::vector<std::int64_t>{0, 1}));
  try {
    read_text("VERTEX_SE2 0 0 0 0\nFIX 0 4\n");
    FAIL() << "FIX of an unknown vertex was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "id");
  }
}

}  // namespace
}  // namespace slamkit
