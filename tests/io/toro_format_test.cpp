// TORO reader/writer: EDGE2 information order and rotation, EQUIV, 3D records, round trips
// and the g2o ↔ TORO conversion against the SE-Sync conversion of CSAIL.
#include <gtest/gtest.h>

#include <random>

#include "graph_compare.h"
#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/information_conventions.h"
#include "slamkit/io/pose_graph_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

using testing::read_text;
using testing::same_graph;

TEST(ToroFormat, ReadsEdge2InTheToroOrderAndRotatesTheInformation) {
  const double dtheta = 0.7;
  const PoseGraph g = read_text("VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0.7\nEDGE2 0 1 1 0 0.7 11 12 22 33 13 23\n", "t.graph");
  Eigen::Matrix3d toro;
  toro << 11, 12, 13, 12, 22, 23, 13, 23, 33;
  ASSERT_EQ(g.edges.size(), 1u);
  EXPECT_TRUE(g.edges[0].information.isApprox(toro2d_to_g2o_information(toro, dtheta), 1e-15));
  EXPECT_EQ(g.edges[0].information(2, 2), 33.0);
  EXPECT_NEAR(g.edges[0].information.trace(), 66.0, 1e-12);  // rotation keeps the trace
}

TEST(ToroFormat, KeepsEquivalencesAndWritesThemBack) {
  SLAMKIT_REQUIRE_DATA(path, "posegraph/2d/toro/w100.graph");
  const PoseGraph a = read_pose_graph(path.string());
  EXPECT_EQ(a.format, "toro");
  ASSERT_EQ(a.equivalences.size(), 40u);
  EXPECT_EQ(a.equivalences[0], std::make_pair(std::int64_t{21}, std::int64_t{1}));
  EXPECT_EQ(count_connected_components(a), 1u);
  const PoseGraph b = read_text(pose_graph_to_string(a, PoseGraphFormat::kToro), "w.graph");
  EXPECT_TRUE(same_graph(a, b, 0.0, 1e-15));  // poses bit-identical, Ω through cos/sin
  EXPECT_EQ(a.equivalences, b.equivalences);
}

TEST(ToroFormat, ReproducesTheSeSyncConversionOfCsail) {
  SLAMKIT_REQUIRE_DATA(toro_path, "posegraph/2d/toro/CSAIL_P_toro.graph");
  SLAMKIT_REQUIRE_DATA(g2o_path, "posegraph/2d/derived/CSAIL_P_toro.g2o");
  const PoseGraph toro = read_pose_graph(toro_path.string());
  const PoseGraph g2o = read_pose_graph(g2o_path.string());
  // Same numbers printed: vertices and measurements bit-identical.
  ASSERT_TRUE(same_graph(toro, g2o, 0.0, 1e-6));
  // Information: the derived file prints 6 decimals, so every entry agrees to half a unit of
  // the 6th decimal; and the 2D rotation is needed: without it most edges would differ.
  double worst = 0.0;
  std::size_t rotated = 0;
  for (std::size_t k = 0; k < toro.edges.size(); ++k) {
    const Eigen::MatrixXd& a = toro.edges[k].information;
    const Eigen::MatrixXd& b = g2o.edges[k].information;
    worst = std::max(worst, (a - b).cwiseAbs().maxCoeff());
    const Eigen::Matrix3d unrotated = g2o_to_toro2d_information(a, 0.0);
    rotated += (unrotated - g2o_to_toro2d_information(a, toro.edges[k].pose2.theta())).cwiseAbs().maxCoeff() > 1e-3;
  }
  EXPECT_LE(worst, 5.0e-7 + 1e-12);
  EXPECT_GT(rotated, toro.edges.size() / 2);
  const double chi2_toro = total_chi2(toro), chi2_g2o = total_chi2(g2o);
  // 1e-10 relative: the 6-decimal information of the derived file allows ~4e-12 here.
  EXPECT_NEAR(chi2_toro / chi2_g2o, 1.0, 1e-10) << chi2_toro << " vs " << chi2_g2o;
}

Eigen::Matrix3d random_information(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3d a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a(r, c) = u(rng);
  return a * a.transpose() * 100.0 + Eigen::Matrix3d::Identity();
}

TEST(ToroFormat, G2oToToroToG2oPreservesInformation) {
  // Random full information matrices (cross terms with θ included) and angles all around.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  PoseGraph g;
  for (int i = 0; i < 50; ++i) {
    GraphVertex v;
    v.id = i;
    v.pose2 = SE2(u(rng), u(rng), u(rng));
    g.add_vertex(v);
  }
  for (int i = 0; i < 50; ++i) {
    GraphEdge e;
    e.from = i;
    e.to = (i + 7) % 50;
    e.pose2 = SE2(u(rng), u(rng), u(rng));
    e.information = random_information(rng);
    g.edges.push_back(e);
  }
  const PoseGraph back = read_text(pose_graph_to_string(g, PoseGraphFormat::kToro), "r.graph");
  EXPECT_TRUE(same_graph(g, back, 0.0, 1e-12));
  const PoseGraph again = read_text(pose_graph_to_string(back, PoseGraphFormat::kG2o), "r.g2o");
  EXPECT_TRUE(same_graph(back, again, 0.0, 0.0));
  EXPECT_NEAR(total_chi2(back) / total_chi2(g), 1.0, 1e-12);
}

TEST(ToroFormat, G2oDatasetThroughToroKeepsChi2) {
  SLAMKIT_REQUIRE_DATA(path, "posegraph/2d/input_INTEL_g2o.g2o");
  const PoseGraph g = read_pose_graph(path.string());
  const PoseGraph t = read_text(pose_graph_to_string(g, PoseGraphFormat::kToro), "intel.graph");
  EXPECT_TRUE(same_graph(g, t, 0.0, 1e-12));
  EXPECT_NEAR(total_chi2(t) / total_chi2(g), 1.0, 1e-12);
}

TEST(ToroFormat, ThreeDimensionalRecordsRoundTrip) {
  const std::string text =
      "VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 1.5 -2 0.25 0.1 -0.2 2.5\n"
      "EDGE3 0 1 1.5 -2 0.25 0.1 -0.2 2.5 10 1 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 25\n";
  PoseGraphReadReport r;
  const PoseGraph a = read_text(text, "g.graph", {}, &r);
  EXPECT_EQ(r.format, PoseGraphFormat::kToro);
  EXPECT_EQ(a.dimension(), 3);
  EXPECT_NEAR(total_chi2(a), 0.0, 1e-20);
  EXPECT_EQ(a.edges[0].information(3, 3), 400.0);
  EXPECT_EQ(a.edges[0].information(0, 1), 1.0);
  const PoseGraph b = read_text(pose_graph_to_string(a, PoseGraphFormat::kToro), "g.graph");
  EXPECT_TRUE(same_graph(a, b, 1e-15, 0.0));
}

}  // namespace
}  // namespace slamkit
