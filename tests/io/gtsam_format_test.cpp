// GTSAM EDGE3 text: roll/pitch/yaw measurements, information on the rotation vector (×4 to
// g2o), round trips, and sphere2500 in both formats.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>
#include <map>

#include "graph_compare.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

using testing::read_text;
using testing::same_graph;

TEST(GtsamFormat, ReadsRollPitchYawAndScalesRotationInformation) {
  const PoseGraph g = read_text(
      "EDGE3 3 4 1 2 3 0.1 0.2 0.3 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21\n", "s.txt");
  ASSERT_EQ(g.edges.size(), 1u);
  const GraphEdge& e = g.edges[0];
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX())).toRotationMatrix();
  EXPECT_TRUE(e.pose3.rotation().matrix().isApprox(R, 1e-15));
  EXPECT_EQ(e.pose3.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(e.information(0, 0), 1.0);   // t-t unchanged
  EXPECT_EQ(e.information(0, 3), 8.0);   // t-rot ×2 (I14 = 4)
  EXPECT_EQ(e.information(3, 3), 64.0);  // rot-rot ×4 (I44 = 16)
  EXPECT_EQ(e.information(5, 5), 84.0);  // I66 = 21
  EXPECT_EQ(e.information(5, 3), e.information(3, 5));
  // Edges-only: vertices 3 and 4 from the odometry, the first at the identity.
  EXPECT_TRUE(g.vertex(3).pose3.translation().isZero());
  EXPECT_NEAR(total_chi2(g), 0.0, 1e-20);
}

TEST(GtsamFormat, RoundTripKeepsInformationExactly) {
  SLAMKIT_REQUIRE_DATA(path, "posegraph/3d/gtsam_txt/sphere2500.txt");
  const PoseGraph a = read_pose_graph(path.string());
  EXPECT_EQ(a.format, "gtsam");
  const PoseGraph b = read_text(pose_graph_to_string(a, PoseGraphFormat::kGtsam), "b.txt");
  EXPECT_TRUE(same_graph(a, b, 1e-14, 0.0));
  // g2o → GTSAM → g2o: information bit-identical (×¼, ×4), rotations to rounding.
  SLAMKIT_REQUIRE_DATA(g2o_path, "posegraph/3d/tinyGrid3D.g2o");
  const PoseGraph c = read_pose_graph(g2o_path.string());
  const PoseGraph d = read_text(pose_graph_to_string(c, PoseGraphFormat::kGtsam), "grid.txt");
  EXPECT_TRUE(same_graph(c, d, 1e-14, 0.0));
  EXPECT_NEAR(total_chi2(d) / total_chi2(c), 1.0, 1e-12);
}

TEST(GtsamFormat, RollPitchYawRoundTripHoldsAtGimbalLock) {
  // Near |pitch| = π/2 roll and yaw are each ill-determined; the written angles must still
  // reproduce the rotation (found by fuzzing: pitch 1.5707963267946, yaw 986).
  for (const double pitch : {1.5707963267946, 1.5707963267948966, -1.5707963267948966, 1.5707963, 0.3}) {
    for (const double yaw : {986.0, -2.0, 0.0}) {
      char text[128];
      std::snprintf(text, sizeof(text), "VERTEX3 0 0 0 0 0.7 %.17g %.17g\n", pitch, yaw);
      const PoseGraph a = read_text(text, "g.txt");
      const PoseGraph b = read_text(pose_graph_to_string(a, PoseGraphFormat::kGtsam), "g.txt");
      EXPECT_TRUE(testing::same_pose3(a.vertices()[0].pose3, b.vertices()[0].pose3, 1e-14)) << pitch << " " << yaw;
    }
  }
}

// sphere2500.txt (GTSAM) and sphere2500.g2o hold the same edges. Measurements agree to the
// printed precision. The g2o file's rotation information is NOT exactly 4× the GTSAM one:
// it was converted by some other (measurement-dependent) rule, off by up to ~3% per
// eigenvalue and ~9% per entry. So the check is: same translation information, rotation
// eigenvalues within 5%, and the same chi2 within 1% at the ground truth (where the
// rotation residuals matter; the wrong factor ×1 would give −12%).
TEST(GtsamFormat, Sphere2500AgreesWithTheG2oVersion) {
  SLAMKIT_REQUIRE_DATA(txt_path, "posegraph/3d/gtsam_txt/sphere2500.txt");
  SLAMKIT_REQUIRE_DATA(g2o_path, "posegraph/3d/sphere2500.g2o");
  SLAMKIT_REQUIRE_DATA(gt_path, "posegraph/3d/gtsam_txt/sphere2500_groundtruth.txt");
  PoseGraph txt = read_pose_graph(txt_path.string());
  PoseGraph g2o = read_pose_graph(g2o_path.string());
  ASSERT_EQ(txt.edges.size(), g2o.edges.size());
  std::map<std::pair<std::int64_t, std::int64_t>, const GraphEdge*> by_ids;
  for (const GraphEdge& e : g2o.edges) by_ids[{e.from, e.to}] = &e;
  double worst_angle = 0.0, worst_eigen = 0.0;
  for (const GraphEdge& e : txt.edges) {
    const auto it = by_ids.find({e.from, e.to});
    ASSERT_NE(it, by_ids.end()) << e.from << "-" << e.to;
    const GraphEdge& f = *it->second;
    EXPECT_EQ(e.pose3.translation(), f.pose3.translation());  // identical digits
    worst_angle = std::max(worst_angle, e.pose3.rotation().between(f.pose3.rotation()).log().norm());
    EXPECT_EQ(e.information.topLeftCorner(3, 3), f.information.topLeftCorner(3, 3));
    EXPECT_TRUE(e.information.topRightCorner(3, 3).isZero());
    EXPECT_TRUE(f.information.topRightCorner(3, 3).isZero());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> a(e.information.bottomRightCorner(3, 3));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> b(f.information.bottomRightCorner(3, 3));
    worst_eigen = std::max(worst_eigen, (b.eigenvalues().array() / a.eigenvalues().array() - 1.0).abs().maxCoeff());
  }
  EXPECT_LT(worst_angle, 2e-6);  // 6 significant digits of roll/pitch/yaw
  EXPECT_LT(worst_eigen, 0.05);
  // chi2 at the ground-truth poses.
  const PoseGraph gt = read_pose_graph(gt_path.string());
  for (std::size_t i = 0; i < txt.vertices().size(); ++i) txt.vertex_at(i).pose3 = gt.vertex(txt.vertices()[i].id).pose3;
  for (std::size_t i = 0; i < g2o.vertices().size(); ++i) g2o.vertex_at(i).pose3 = gt.vertex(g2o.vertices()[i].id).pose3;
  EXPECT_NEAR(total_chi2(txt) / total_chi2(g2o), 1.0, 0.01);
}

}  // namespace
}  // namespace slamkit
