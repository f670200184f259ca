// The information conversions are the exact first-order relation between the formats'
// error vectors: check eᵀ_src Ω_src e_src = eᵀ_g2o Ω_g2o e_g2o for small errors.
#include "slamkit/io/information_conventions.h"

#include <gtest/gtest.h>

#include <random>

#include "slamkit/core/pose_graph_error.h"

namespace slamkit {
namespace {

Eigen::MatrixXd random_spd(std::mt19937& rng, int n) {
  std::normal_distribution<double> g;
  Eigen::MatrixXd a(n, n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) a(r, c) = g(rng);
  return a * a.transpose() + Eigen::MatrixXd::Identity(n, n);
}

TEST(InformationConventions, UpperTriangleIsRowMajor) {
  const double v[6] = {11, 12, 13, 22, 23, 33};
  Eigen::Matrix3d want;
  want << 11, 12, 13, 12, 22, 23, 13, 23, 33;
  EXPECT_EQ(Eigen::Matrix3d(symmetric_from_upper_triangle(v, 3)), want);
}

TEST(InformationConventions, Toro2dResidualIsRotatedByTheMeasuredAngle) {
  // TORO's residual of an edge: translation difference in the frame of pose i, angle difference.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 50; ++trial) {
    const SE2 Z(u(rng), u(rng), u(rng));
    const SE2 Xi(u(rng), u(rng), u(rng));
    const Eigen::Vector3d delta = 1e-6 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    const SE2 Xj = Xi * Z * SE2::exp(delta);
    const SE2 A = Xi.between(Xj);
    const Eigen::Vector3d e_toro(A.x() - Z.x(), A.y() - Z.y(), wrap_angle(A.theta() - Z.theta()));
    const Eigen::Vector3d e_g2o = pose2_edge_error(Z, Xi, Xj);

    const Eigen::Matrix3d omega_toro = random_spd(rng, 3);
    const Eigen::Matrix3d omega_g2o = toro2d_to_g2o_information(omega_toro, Z.theta());
    const double chi2_toro = e_toro.dot(omega_toro * e_toro);
    const double chi2_g2o = e_g2o.dot(omega_g2o * e_g2o);
    EXPECT_NEAR(chi2_g2o / chi2_toro, 1.0, 1e-5);  // second-order terms: O(|δ|)
    // The README's statement of the xy block, and the cross terms rotated alike.
    const Eigen::Matrix2d R = Z.rotation().matrix();
    const Eigen::Matrix2d xy = R.transpose() * omega_toro.topLeftCorner<2, 2>() * R;
    EXPECT_TRUE((omega_g2o.topLeftCorner<2, 2>().isApprox(xy, 1e-13)));
    const Eigen::Vector2d cross = R.transpose() * omega_toro.topRightCorner<2, 1>();
    EXPECT_TRUE((omega_g2o.topRightCorner<2, 1>().isApprox(cross, 1e-13)));
    EXPECT_EQ(omega_g2o(2, 2), omega_toro(2, 2));
    // Inverse.
    EXPECT_TRUE(g2o_to_toro2d_information(omega_g2o, Z.theta()).isApprox(omega_toro, 1e-13));
  }
}

TEST(InformationConventions, RotationVectorInformationIsFourTimesTheQuaternionOne) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 50; ++trial) {
    const SE3 Z = SE3::exp((Vector6d() << g(rng), g(rng), g(rng), g(rng), g(rng), g(rng)).finished());
    const SE3 Xi = SE3::exp((Vector6d() << g(rng), g(rng), g(rng), g(rng), g(rng), g(rng)).finished());
    const Vector6d delta = 1e-6 * (Vector6d() << g(rng), g(rng), g(rng), g(rng), g(rng), g(rng)).finished();
    const SE3 Xj = Xi * Z * SE3::exp(delta);
    const SE3 E = Z.between(Xi.between(Xj));
    Vector6d e_rv;  // GTSAM EDGE3 / TORO 3D: [t; rotation vector]
    e_rv << E.translation(), E.rotation().log();
    const Vector6d e_g2o = pose3_edge_error(Z, Xi, Xj);

    const Eigen::MatrixXd omega = random_spd(rng, 6);
    const Eigen::MatrixXd omega_g2o = rotation_vector_to_g2o_information(omega);
    EXPECT_NEAR(e_g2o.dot(omega_g2o * e_g2o) / e_rv.dot(omega * e_rv), 1.0, 1e-5);
    EXPECT_EQ(omega_g2o.topLeftCorner(3, 3), omega.topLeftCorner(3, 3));
    EXPECT_EQ(omega_g2o.topRightCorner(3, 3), 2.0 * omega.topRightCorner(3, 3));
    EXPECT_EQ(omega_g2o.bottomRightCorner(3, 3), 4.0 * omega.bottomRightCorner(3, 3));
    EXPECT_EQ(g2o_to_rotation_vector_information(omega_g2o), omega);  // powers of two: exact
  }
}

}  // namespace
}  // namespace slamkit
