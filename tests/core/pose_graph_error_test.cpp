#include "slamkit/core/pose_graph_error.h"

#include <gtest/gtest.h>

#include <random>

#include "testing/numeric_jacobian.h"

namespace slamkit {
namespace {

using testing::jacobians_match;
using testing::numeric_jacobian;

SE3 random_se3(std::mt19937& rng, double angle_scale = 1.0) {
  std::normal_distribution<double> n;
  SE3::Tangent t;
  t << 3 * n(rng), 3 * n(rng), 3 * n(rng), angle_scale * n(rng), angle_scale * n(rng), angle_scale * n(rng);
  return SE3::exp(t);
}
SE2 random_se2(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return SE2(3 * n(rng), 3 * n(rng), 2 * n(rng));
}

TEST(PoseGraphError, Pose3JacobiansMatchNumeric) {
  std::mt19937 rng(1);
  for (int i = 0; i < 50; ++i) {
    // Small residuals (near a solution) and arbitrary ones, incl. rotations near π.
    const SE3 Xi = random_se3(rng), Xj = random_se3(rng);
    const SE3 Z = i % 2 ? Xi.between(Xj) * random_se3(rng, 0.05) : random_se3(rng, 1.2);
    Matrix6d Ji, Jj;
    const Vector6d e0 = pose3_edge_error(Z, Xi, Xj, &Ji, &Jj);
    auto gi = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose3_edge_error(Z, Xi.plus(SE3::Tangent(d)), Xj) - e0;
    };
    auto gj = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose3_edge_error(Z, Xi, Xj.plus(SE3::Tangent(d))) - e0;
    };
    if (std::abs(Z.between(Xi.between(Xj)).rotation().quaternion().w()) < 1e-3) continue;  // sign flip
    EXPECT_TRUE(jacobians_match(Ji, numeric_jacobian(gi, 6), 1e-6, "J_e_Xi"));
    EXPECT_TRUE(jacobians_match(Jj, numeric_jacobian(gj, 6), 1e-6, "J_e_Xj"));
  }
}

TEST(PoseGraphError, Pose2JacobiansMatchNumeric) {
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    const SE2 Xi = random_se2(rng), Xj = random_se2(rng), Z = random_se2(rng);
    Eigen::Matrix3d Ji, Jj;
    const Eigen::Vector3d e0 = pose2_edge_error(Z, Xi, Xj, &Ji, &Jj);
    if (std::abs(e0.z()) > kPi - 1e-3) continue;  // angle wrap
    auto gi = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose2_edge_error(Z, Xi.plus(SE2::Tangent(d)), Xj) - e0;
    };
    auto gj = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose2_edge_error(Z, Xi, Xj.plus(SE2::Tangent(d))) - e0;
    };
    EXPECT_TRUE(jacobians_match(Ji, numeric_jacobian(gi, 3), 1e-6, "J_e_Xi"));
    EXPECT_TRUE(jacobians_match(Jj, numeric_jacobian(gj, 3), 1e-6, "J_e_Xj"));
  }
}

TEST(PoseGraphError, PointJacobiansMatchNumeric) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  for (int i = 0; i < 30; ++i) {
    const SE2 X2 = random_se2(rng);
    const Eigen::Vector2d p2(4 * n(rng), 4 * n(rng)), z2(n(rng), n(rng));
    Eigen::Matrix<double, 2, 3> JX2;
    Eigen::Matrix2d Jp2;
    const Eigen::Vector2d e2 = pose2_point_error(z2, X2, p2, &JX2, &Jp2);
    EXPECT_TRUE(jacobians_match(JX2, numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose2_point_error(z2, X2.plus(SE2::Tangent(d)), p2) - e2; }, 3), 1e-6, "J_e_X (2D)"));
    EXPECT_TRUE(jacobians_match(Jp2, numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose2_point_error(z2, X2, p2 + Eigen::Vector2d(d)) - e2; }, 2), 1e-6, "J_e_p (2D)"));

    const SE3 X3 = random_se3(rng), O = random_se3(rng, 0.3);
    const Eigen::Vector3d p3(4 * n(rng), 4 * n(rng), 4 * n(rng)), z3(n(rng), n(rng), n(rng));
    Eigen::Matrix<double, 3, 6> JX3;
    Eigen::Matrix3d Jp3;
    const Eigen::Vector3d e3 = pose3_point_error(z3, X3, O, p3, &JX3, &Jp3);
    EXPECT_TRUE(e3.isApprox((X3 * O).inverse().act(p3) - z3, 1e-12));
    EXPECT_TRUE(jacobians_match(JX3, numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose3_point_error(z3, X3.plus(SE3::Tangent(d)), O, p3) - e3; }, 6), 1e-6, "J_e_X (3D)"));
    EXPECT_TRUE(jacobians_match(Jp3, numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return pose3_point_error(z3, X3, O, p3 + Eigen::Vector3d(d)) - e3; }, 3), 1e-6, "J_e_p (3D)"));
  }
}

TEST(PoseGraphError, Pose3ErrorIsTranslationAndQuaternionVector) {
  // Hand-built case: Xi = I, Xj = (Rz(0.4), t), Z = I ⇒ e = [t; (0, 0, sin 0.2)].
  const SE3 Xj(SO3::exp(Eigen::Vector3d(0, 0, 0.4)), Eigen::Vector3d(1, 2, 3));
  const Vector6d e = pose3_edge_error(SE3(), SE3(), Xj);
  Vector6d expected;
  expected << 1, 2, 3, 0, 0, std::sin(0.2);
  EXPECT_TRUE(e.isApprox(expected, 1e-14));
  // A rotation beyond π about z is represented with w ≥ 0: the vector part flips sign.
  const SE3 Xk(SO3(Eigen::Quaterniond(-0.1, 0, 0, std::sqrt(0.99))), Eigen::Vector3d::Zero());
  EXPECT_LT(pose3_edge_error(SE3(), SE3(), Xk)(5), 0.0);
}

}  // namespace
}  // namespace slamkit
