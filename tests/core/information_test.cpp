#include "slamkit/core/information.h"

#include <gtest/gtest.h>

namespace slamkit {
namespace {

TEST(Information, Classifies) {
  EXPECT_EQ(check_information(Eigen::Matrix3d::Identity()).status, InformationStatus::kPositiveDefinite);
  Eigen::Matrix3d singular = Eigen::Matrix3d::Identity();
  singular(2, 2) = 0.0;
  EXPECT_EQ(check_information(singular).status, InformationStatus::kSingular);
  Eigen::Matrix3d indefinite = Eigen::Matrix3d::Identity();
  indefinite(2, 2) = -0.5;
  EXPECT_EQ(check_information(indefinite).status, InformationStatus::kIndefinite);
  Eigen::Matrix3d asym = Eigen::Matrix3d::Identity();
  asym(0, 1) = 0.3;
  EXPECT_EQ(check_information(asym).status, InformationStatus::kNotSymmetric);
  Eigen::Matrix3d nan = Eigen::Matrix3d::Identity();
  nan(1, 1) = std::nan("");
  EXPECT_EQ(check_information(nan).status, InformationStatus::kNotFinite);
}

TEST(Information, ProjectionIsPositiveDefiniteAndKeepsGoodPart) {
  Eigen::Matrix3d A;
  A << 4, 1, 0, 1, -2, 0.5, 0, 0.5, 3;
  const Eigen::MatrixXd P = project_to_psd(A);
  const InformationCheck c = check_information(P);
  EXPECT_EQ(c.status, InformationStatus::kPositiveDefinite);
  EXPECT_NEAR(c.min_eigenvalue, 1e-9 * c.max_eigenvalue, 1e-12);
  // A PD matrix is a fixed point.
  Eigen::Matrix3d B;
  B << 4, 1, 0, 1, 2, 0.5, 0, 0.5, 3;
  EXPECT_TRUE(project_to_psd(B).isApprox(B, 1e-12));
}

TEST(Information, GraphHealthAndRepair) {
  PoseGraph g;
  g.add_vertex({0, VertexKind::kPose2});
  g.add_vertex({1, VertexKind::kPose2});
  GraphEdge e;
  e.from = 0, e.to = 1, e.information = Eigen::Matrix3d::Identity(), e.line = 3;
  g.edges.push_back(e);
  e.information(1, 1) = -1.0, e.line = 4;
  g.edges.push_back(e);
  InformationHealth h = check_information(g);
  EXPECT_EQ(h.positive_definite, 1u);
  EXPECT_EQ(h.indefinite, 1u);
  EXPECT_EQ(h.first_bad_line, 4);
  EXPECT_EQ(repair_information(g), 1u);
  EXPECT_EQ(check_information(g).bad(), 0u);
}

}  // namespace
}  // namespace slamkit
