// Analytic Jacobians of the filter models against central differences.
#include "slamkit/filters/models.h"

#include <gtest/gtest.h>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"
#include "testing/numeric_jacobian.h"

namespace slamkit {
namespace {

using testing::jacobians_match;
using testing::numeric_jacobian;

Eigen::VectorXd wrapped_difference(Eigen::VectorXd a, const Eigen::VectorXd& b, int angle_row) {
  a -= b;
  a(angle_row) = wrap_angle(a(angle_row));
  return a;
}

void check_motion_model(const MotionModel& model, const Eigen::Vector3d& x, const Control& u) {
  Eigen::Matrix3d F_x;
  Eigen::Matrix<double, 3, 2> F_u;
  model.jacobians(x, u, &F_x, &F_u);
  const Eigen::Vector3d y0 = model.predict(x, u);
  auto wrt_pose = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return wrapped_difference(model.predict(x + d, u), y0, 2);
  };
  auto wrt_control = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    Control v = u;
    v.v += d(0);
    v.turn += d(1);
    return wrapped_difference(model.predict(x, v), y0, 2);
  };
  EXPECT_TRUE(jacobians_match(F_x, numeric_jacobian(wrt_pose, 3), 1e-7, "F_x"));
  EXPECT_TRUE(jacobians_match(F_u, numeric_jacobian(wrt_control, 2), 1e-7, "F_u"));
}

TEST(FilterModels, BicycleJacobiansMatchNumeric) {
  const BicycleModel model(4.0, 0.3, 0.05);
  check_motion_model(model, {1.0, -2.0, 0.7}, {3.0, 0.2, 0.025});
  check_motion_model(model, {0.0, 0.0, 3.1}, {2.0, -0.5, 0.2});  // heading near ±π
}

TEST(FilterModels, UnicycleJacobiansMatchNumeric) {
  const UnicycleModel model(0.1, 0.05, 0.1, 0.1);
  check_motion_model(model, {1.0, -2.0, 0.7}, {0.4, 0.3, 0.1});
  check_motion_model(model, {0.0, 0.0, -3.1}, {0.2, -0.8, 0.5});
}

TEST(FilterModels, RangeBearingJacobiansMatchNumeric) {
  const RangeBearingModel model(0.1, 0.02);
  const Eigen::Vector3d x(1.0, 2.0, 2.9);
  const Eigen::Vector2d m(-3.0, 2.5);  // bearing near ±π from this heading
  Eigen::Matrix<double, 2, 3> H_x;
  Eigen::Matrix2d H_m;
  model.jacobians(x, m, &H_x, &H_m);
  const Eigen::Vector2d z0 = model.predict(x, m);
  auto wrt_pose = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return wrapped_difference(model.predict(x + d, m), z0, 1);
  };
  auto wrt_landmark = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return wrapped_difference(model.predict(x, m + d), z0, 1);
  };
  EXPECT_TRUE(jacobians_match(H_x, numeric_jacobian(wrt_pose, 3), 1e-7, "H_x"));
  EXPECT_TRUE(jacobians_match(H_m, numeric_jacobian(wrt_landmark, 2), 1e-7, "H_m"));
}

TEST(FilterModels, InverseObservationRoundTripsAndItsJacobiansMatch) {
  const RangeBearingModel model(0.1, 0.02);
  const Eigen::Vector3d x(1.0, 2.0, -0.4);
  RangeBearing z;
  z.range = 7.5;
  z.bearing = 2.8;
  Eigen::Matrix<double, 2, 3> G_x;
  Eigen::Matrix2d G_z;
  const Eigen::Vector2d m = model.inverse(x, z, &G_x, &G_z);
  const Eigen::Vector2d back = model.predict(x, m);
  EXPECT_NEAR(back.x(), z.range, 1e-12);
  EXPECT_NEAR(wrap_angle(back.y() - z.bearing), 0.0, 1e-12);
  auto wrt_pose = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return model.inverse(x + d, z);
  };
  auto wrt_observation = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    RangeBearing w = z;
    w.range += d(0);
    w.bearing += d(1);
    return model.inverse(x, w);
  };
  EXPECT_TRUE(jacobians_match(G_x, numeric_jacobian(wrt_pose, 3), 1e-7, "G_x"));
  EXPECT_TRUE(jacobians_match(G_z, numeric_jacobian(wrt_observation, 2), 1e-7, "G_z"));
}

TEST(FilterModels, InnovationWrapsTheBearing) {
  RangeBearing z;
  z.range = 5.0;
  z.bearing = 3.1;
  const Eigen::Vector2d nu = RangeBearingModel::innovation(z, Eigen::Vector2d(4.0, -3.1));
  EXPECT_NEAR(nu.x(), 1.0, 1e-12);
  EXPECT_NEAR(nu.y(), 6.2 - 2 * kPi, 1e-12);
}

TEST(FilterModels, BadNoiseIsRejected) {
  EXPECT_THROW(BicycleModel(0.0, 0.3, 0.05), InputError);
  EXPECT_THROW(RangeBearingModel(0.1, std::nan("")), InputError);
  EXPECT_THROW(UnicycleModel(-1.0, 0.1), InputError);
}

}  // namespace
}  // namespace slamkit
