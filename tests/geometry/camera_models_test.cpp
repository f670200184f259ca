// Camera models: analytic Jacobians against central differences, project ∘ unproject over
// the whole image, and the known projection of simple points.
#include "slamkit/geometry/camera_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "testing/numeric_jacobian.h"

namespace slamkit {
namespace {

// TUM-VI cam0 and EuRoC cam0 (the numbers of ../shared/datasets/vio/README.md).
std::shared_ptr<CameraModel> tumvi() {
  return std::make_shared<EquidistantCamera>(190.97847715128717, 190.9733070521226, 254.93170605935475,
                                             256.8974428996504, 0.0034823894022493434, 0.0007150348452162257,
                                             -0.0020532361418706202, 0.00020293673591811182, 512, 512);
}
std::shared_ptr<CameraModel> euroc() {
  return std::make_shared<RadTanCamera>(458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
                                        1.76187114e-05, 752, 480);
}
std::shared_ptr<CameraModel> pinhole() { return std::make_shared<PinholeCamera>(500, 480, 320, 240, 640, 480); }

std::vector<std::shared_ptr<CameraModel>> all_models() { return {pinhole(), euroc(), tumvi()}; }

Eigen::Vector2d project_or_nan(const CameraModel& cam, const Eigen::Vector3d& p) {
  Eigen::Vector2d uv = Eigen::Vector2d::Constant(NAN);
  cam.project(p, &uv);
  return uv;
}

TEST(CameraModels, PointJacobiansMatchNumeric) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xy(-1.2, 1.2), z(0.5, 4.0);
  for (const auto& cam : all_models()) {
    int checked = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const Eigen::Vector3d p(xy(rng), xy(rng), z(rng));
      Eigen::Vector2d uv;
      Eigen::Matrix<double, 2, 3> J;
      if (!cam->project(p, &uv, &J) || !cam->in_image(uv)) continue;
      const auto g = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
        return project_or_nan(*cam, p + Eigen::Vector3d(d)) - uv;
      };
      ASSERT_TRUE(testing::jacobians_match(J, testing::numeric_jacobian(g, 3, 1e-6), 1e-5, cam->model_name()));
      ++checked;
    }
    EXPECT_GT(checked, 50) << cam->model_name();
  }
}

TEST(CameraModels, FisheyeJacobianBeyondNinetyDegreesAndOnAxis) {
  const auto cam = tumvi();
  for (const Eigen::Vector3d p : {Eigen::Vector3d(1.0, 0.3, -0.1), Eigen::Vector3d(0.0, 0.0, 2.0),
                                  Eigen::Vector3d(1e-12, -1e-12, 1.0), Eigen::Vector3d(-0.5, 2.0, 0.0)}) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    ASSERT_TRUE(cam->project(p, &uv, &J)) << p.transpose();
    const auto g = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return project_or_nan(*cam, p + Eigen::Vector3d(d)) - uv;
    };
    EXPECT_TRUE(testing::jacobians_match(J, testing::numeric_jacobian(g, 3, 1e-7), 1e-4)) << p.transpose();
  }
}

TEST(CameraModels, IntrinsicJacobiansMatchNumeric) {
  for (const auto& cam : all_models()) {
    const Eigen::VectorXd k0 = cam->intrinsics();
    for (const Eigen::Vector3d p : {Eigen::Vector3d(0.3, -0.2, 1.5), Eigen::Vector3d(-0.9, 0.4, 1.2),
                                    Eigen::Vector3d(1e-13, 0.0, 2.0)}) {
      Eigen::Vector2d uv;
      Eigen::Matrix<double, 2, Eigen::Dynamic> J;
      ASSERT_TRUE(cam->project(p, &uv, nullptr, &J));
      ASSERT_EQ(J.cols(), k0.size());
      const auto g = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
        return project_or_nan(*cam->with_intrinsics(k0 + d), p) - uv;
      };
      EXPECT_TRUE(testing::jacobians_match(J, testing::numeric_jacobian(g, static_cast<int>(k0.size()), 1e-7), 1e-5,
                                           cam->model_name()));
    }
  }
}

TEST(CameraModels, UnprojectThenProjectRoundTripsOverTheImage) {
  for (const auto& cam : all_models()) {
    double worst = 0.0;
    int failures = 0;
    for (int v = 0; v < cam->height(); v += 8) {
      for (int u = 0; u < cam->width(); u += 8) {
        const Eigen::Vector2d uv(u + 0.5, v + 0.5);
        Eigen::Vector3d bearing;
        Eigen::Vector2d back;
        if (!cam->unproject(uv, &bearing) || !cam->project(bearing, &back)) {
          ++failures;
          continue;
        }
        EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
        worst = std::max(worst, (back - uv).norm());
      }
    }
    EXPECT_EQ(failures, 0) << cam->model_name();
    EXPECT_LT(worst, 1e-6) << cam->model_name();
  }
}

TEST(CameraModels, ProjectThenUnprojectGivesTheDirection) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (const auto& cam : all_models()) {
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d p(n(rng), n(rng), std::abs(n(rng)) + 0.2);
      Eigen::Vector2d uv;
      Eigen::Vector3d b;
      if (!cam->project(p, &uv) || !cam->in_image(uv)) continue;
      ASSERT_TRUE(cam->unproject(uv, &b));
      EXPECT_LT((b - p.normalized()).norm(), 1e-9);
      ++checked;
    }
    EXPECT_GT(checked, 100);
  }
}

TEST(CameraModels, PrincipalPointAndEquidistantAngle) {
  const auto cam = tumvi();
  Eigen::Vector2d uv;
  ASSERT_TRUE(cam->project(Eigen::Vector3d(0, 0, 3), &uv));
  EXPECT_NEAR(uv.x(), 254.93170605935475, 1e-12);
  EXPECT_NEAR(uv.y(), 256.8974428996504, 1e-12);
  // 45° off axis along x: θ_d = θ(1 + k1θ² + ...), u = fx θ_d + cx.
  const double th = M_PI / 4, t2 = th * th;
  const double td = th * (1 + 0.0034823894022493434 * t2 + 0.0007150348452162257 * t2 * t2 -
                          0.0020532361418706202 * t2 * t2 * t2 + 0.00020293673591811182 * t2 * t2 * t2 * t2);
  ASSERT_TRUE(cam->project(Eigen::Vector3d(1, 0, 1), &uv));
  EXPECT_NEAR(uv.x(), 190.97847715128717 * td + 254.93170605935475, 1e-9);
  EXPECT_GT(static_cast<const EquidistantCamera&>(*cam).max_theta(), M_PI / 2);
}

TEST(CameraModels, RejectsPointsBehindAndBadParameters) {
  Eigen::Vector2d uv;
  EXPECT_FALSE(pinhole()->project(Eigen::Vector3d(0, 0, -1), &uv));
  EXPECT_FALSE(euroc()->project(Eigen::Vector3d(0.1, 0, 0), &uv));
  EXPECT_FALSE(tumvi()->project(Eigen::Vector3d(0, 0, -1), &uv));
  EXPECT_FALSE(tumvi()->project(Eigen::Vector3d(NAN, 0, 1), &uv));
  EXPECT_THROW(make_camera_model("radtan", {1, 1, 0, 0}, 10, 10), std::invalid_argument);
  EXPECT_THROW(make_camera_model("fov", {1, 1, 0, 0}, 10, 10), std::invalid_argument);
  EXPECT_THROW(make_camera_model("pinhole", {0, 1, 0, 0}, 10, 10), std::invalid_argument);
  EXPECT_THROW(make_camera_model("pinhole", {1, 1, 0, 0}, 0, 10), std::invalid_argument);
  EXPECT_EQ(make_camera_model("equidistant", {1, 1, 0, 0, 0, 0, 0, 0}, 10, 10)->model_name(), "equidistant");
}

}  // namespace
}  // namespace slamkit
