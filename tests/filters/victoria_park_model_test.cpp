// Victoria Park car model: analytic Jacobians against central differences, and the closed
// form on a straight drive.
#include "slamkit/filters/victoria_park_model.h"

#include <gtest/gtest.h>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"
#include "testing/numeric_jacobian.h"

namespace slamkit {
namespace {

using testing::jacobians_match;
using testing::numeric_jacobian;

void check(const MotionModel& model, const Eigen::Vector3d& x, const Control& u) {
  Eigen::Matrix3d F_x;
  Eigen::Matrix<double, 3, 2> F_u;
  model.jacobians(x, u, &F_x, &F_u);
  const Eigen::Vector3d y0 = model.predict(x, u);
  auto diff = [&](Eigen::Vector3d y) -> Eigen::VectorXd {
    y -= y0;
    y.z() = wrap_angle(y.z());
    return y;
  };
  auto wrt_pose = [&](const Eigen::VectorXd& d) { return diff(model.predict(x + d, u)); };
  auto wrt_control = [&](const Eigen::VectorXd& d) {
    Control v = u;
    v.v += d(0);
    v.turn += d(1);
    return diff(model.predict(x, v));
  };
  EXPECT_TRUE(jacobians_match(F_x, numeric_jacobian(wrt_pose, 3), 1e-7, "F_x"));
  EXPECT_TRUE(jacobians_match(F_u, numeric_jacobian(wrt_control, 2), 1e-7, "F_u"));
}

TEST(VictoriaParkModel, JacobiansMatchNumeric) {
  const VictoriaParkModel model(VictoriaParkGeometry{}, 0.5, 0.05);
  check(model, {1.0, -2.0, 0.7}, {3.0, 0.2, 0.025});
  check(model, {0.0, 0.0, 3.1}, {2.0, -0.4, 0.2});
  check(model, {5.0, 1.0, -1.0}, {0.0, 0.3, 0.025});
}

TEST(VictoriaParkModel, StraightDriveAndBadGeometry) {
  const VictoriaParkModel model(VictoriaParkGeometry{}, 0.5, 0.05);
  const Eigen::Vector3d y = model.predict({1, 2, 0.5}, {2.0, 0.0, 0.5});
  EXPECT_NEAR(y.x(), 1 + std::cos(0.5), 1e-12);
  EXPECT_NEAR(y.y(), 2 + std::sin(0.5), 1e-12);
  EXPECT_NEAR(y.z(), 0.5, 1e-12);
  VictoriaParkGeometry bad;
  bad.L = 0;
  EXPECT_THROW(VictoriaParkModel(bad, 0.5, 0.05), InputError);
  EXPECT_THROW(VictoriaParkModel(VictoriaParkGeometry{}, -1, 0.05), InputError);
}

}  // namespace
}  // namespace slamkit
