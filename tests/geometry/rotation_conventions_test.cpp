#include <gtest/gtest.h>

#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {
namespace {

TEST(SO3Conventions, RollPitchYawIsRzRyRx) {
  const double r = 0.3, p = -0.7, y = 2.1;
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(SO3::from_rpy(r, p, y).matrix().isApprox(expected, 1e-14));
  EXPECT_TRUE(SO3::from_rpy(r, p, y).to_rpy().isApprox(Eigen::Vector3d(r, p, y), 1e-12));
}

TEST(SO3Conventions, QuaternionSignDoesNotMatter) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Quaterniond nq(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_TRUE(SO3(q).log().isApprox(SO3(nq).log(), 1e-14));
}

TEST(SO3Conventions, RejectsZeroAndNonFiniteQuaternions) {
  EXPECT_THROW(SO3(Eigen::Quaterniond(0, 0, 0, 0)), std::invalid_argument);
  EXPECT_THROW(SO3(Eigen::Quaterniond(NAN, 0, 0, 1)), std::invalid_argument);
}

TEST(SE2Conventions, ExpIsMatrixExponential) {
  const SE2::Tangent tau(0.4, -1.2, 0.9);
  Eigen::Matrix3d hat = Eigen::Matrix3d::Zero();
  hat(0, 1) = -tau.z();
  hat(1, 0) = tau.z();
  hat(0, 2) = tau.x();
  hat(1, 2) = tau.y();
  // Series of the matrix exponential (converges fast for this small norm).
  Eigen::Matrix3d E = Eigen::Matrix3d::Identity(), term = Eigen::Matrix3d::Identity();
  for (int k = 1; k < 30; ++k) E += (term = term * hat / k);
  EXPECT_TRUE(SE2::exp(tau).matrix().isApprox(E, 1e-13));
}

TEST(SE3Conventions, ExpIsMatrixExponential) {
  SE3::Tangent tau;
  tau << 0.4, -1.2, 0.3, 0.9, -0.2, 0.5;
  Eigen::Matrix4d hat = Eigen::Matrix4d::Zero();
  hat.topLeftCorner<3, 3>() = skew(tau.tail<3>());
  hat.topRightCorner<3, 1>() = tau.head<3>();
  Eigen::Matrix4d E = Eigen::Matrix4d::Identity(), term = Eigen::Matrix4d::Identity();
  for (int k = 1; k < 30; ++k) E += (term = term * hat / k);
  EXPECT_TRUE(SE3::exp(tau).matrix().isApprox(E, 1e-13));
}

TEST(AngleWrap, StaysInHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle(-kPi), kPi);
  EXPECT_NEAR(wrap_angle(3 * kPi + 0.1), -kPi + 0.1, 1e-12);
  EXPECT_NEAR(wrap_angle(-7.0), -7.0 + 2 * kPi, 1e-12);
}

}  // namespace
}  // namespace slamkit

namespace slamkit {
namespace {

TEST(SO3Conventions, RollPitchYawReproducesRotationAtGimbalLock) {
  for (double eps : {0.0, 1e-12, 1e-8, 1e-4})
    for (double sign : {1.0, -1.0}) {
      const SO3 R = SO3::from_rpy(0.7, sign * (kPi / 2 - eps), -1.9);
      const Eigen::Vector3d rpy = R.to_rpy();
      const SO3 back = SO3::from_rpy(rpy.x(), rpy.y(), rpy.z());
      EXPECT_LT((back.matrix() - R.matrix()).norm(), 1e-14) << eps;
    }
}

}  // namespace
}  // namespace slamkit
