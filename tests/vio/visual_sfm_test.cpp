// Visual SfM of the VIO start-up on the synthetic VioScene (pinhole, 1 px noise): it must
// recover the camera poses of a 10-frame window up to one scale; the normalized reprojection
// factor's and the baseline factor's Jacobians against central differences; failures are
// messages, not NaN. (The start-up end to end, SfM + alignment on a simulated run: vio_sim_runner_test.)
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamkit/core/jacobian_check.h"
#include "slamkit/vio/visual_inertial_initializer.h"
#include "slamkit/vio/visual_sfm.h"
#include "testing/vio_scene.h"

namespace slamkit {
namespace {

using testing::VioScene;

// Every `step`-th frame of the scene from `first`, `count` frames.
std::vector<CameraFrame> window(const VioScene& s, int first, int count, int step) {
  std::vector<CameraFrame> w;
  for (int k = 0; k < count; ++k) w.push_back(s.frames.at(first + k * step));
  return w;
}

std::vector<std::vector<SfmObservation>> bearings(const VioScene& s, const std::vector<CameraFrame>& w) {
  std::vector<std::vector<SfmObservation>> out;
  for (const CameraFrame& f : w) {
    out.emplace_back();
    for (const FeatureObservation& o : f.features) {
      SfmObservation b;
      b.track_id = o.track_id;
      EXPECT_TRUE(s.camera->unproject(o.pixel, &b.bearing));
      out.back().push_back(b);
    }
  }
  return out;
}

TEST(NormalizedReprojectionFactor, JacobiansMatchNumeric) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n;
  Values v;
  FactorGraph g;
  for (int i = 0; i < 10; ++i) {
    const SE3 T(SO3::exp(Eigen::Vector3d(n(rng), n(rng), n(rng))), Eigen::Vector3d(n(rng), n(rng), n(rng)));
    const Eigen::Vector3d P = T.act(Eigen::Vector3d(0.5 * n(rng), 0.5 * n(rng), 3.0 + 0.3 * n(rng)));
    v.insert(symbol('c', i), T), v.insert(symbol('p', i), P);
    const NormalizedReprojectionFactor at_truth(symbol('c', i), symbol('p', i),
                                                (T.inverse().act(P) / T.inverse().act(P).z()).head<2>(), NoiseModel::unit(2));
    EXPECT_LT(at_truth.error(T, P, nullptr, nullptr).norm(), 1e-12);
    g.emplace<NormalizedReprojectionFactor>(symbol('c', i), symbol('p', i), Eigen::Vector2d(0.01, -0.02), NoiseModel::unit(2));
    g.emplace<BaselineFactor>(symbol('c', i), NoiseModel::unit(1));
  }
  const JacobianCheckResult r = check_jacobians(g, v, 1e-6);
  EXPECT_TRUE(r.ok) << r.message();
}

TEST(NormalizedReprojectionFactor, PointBehindIsCappedNotNaN) {
  const NormalizedReprojectionFactor f(symbol('c', 0), symbol('p', 0), Eigen::Vector2d::Zero(), NoiseModel::unit(2));
  Eigen::Matrix<double, 2, 6> J_T;
  Eigen::Matrix<double, 2, 3> J_P;
  const Eigen::Vector2d r = f.error(SE3(), Eigen::Vector3d(0, 0, -2), &J_T, &J_P);
  EXPECT_TRUE(r.allFinite() && J_T.isZero() && J_P.isZero());
}

TEST(VisualSfm, RecoversWindowPosesUpToScale) {
  const VioScene scene(1.0, 3.0, 11, 3000);
  const std::vector<CameraFrame> w = window(scene, 0, 10, 4);
  VisualSfmOptions o;
  o.focal_px = 300.0;
  const VisualSfmResult r = solve_visual_sfm(bearings(scene, w), o);
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.T_c0_cam.size(), w.size());
  EXPECT_NEAR(r.T_c0_cam[r.reference_frame].translation().norm(), 1.0, 1e-3);
  EXPECT_LT(r.reprojection_rmse_px, 1.5);
  EXPECT_GT(r.points.size(), 100u);
  const auto cam = [&](const CameraFrame& f) { return scene.motion.state(f.stamp).pose() * scene.T_imu_cam; };
  const SE3 T_w_c0 = cam(w[0]);
  const int j = r.reference_frame;
  const double scale = (T_w_c0.inverse() * cam(w[j])).translation().norm() / r.T_c0_cam[j].translation().norm();
  double extent = 0.0;
  for (std::size_t k = 0; k < w.size(); ++k) extent = std::max(extent, (T_w_c0.inverse() * cam(w[k])).translation().norm());
  ASSERT_GT(extent, 0.3);
  for (std::size_t k = 0; k < w.size(); ++k) {
    const SE3 truth = T_w_c0.inverse() * cam(w[k]);
    const double rot_err = (truth.rotation().inverse() * r.T_c0_cam[k].rotation()).log().norm();
    const double pos_err = (scale * r.T_c0_cam[k].translation() - truth.translation()).norm();
    EXPECT_LT(rot_err, 0.3 * kPi / 180) << "frame " << k;
    EXPECT_LT(pos_err, 0.02 * extent) << "frame " << k;
  }
}

TEST(VisualSfm, NoParallaxIsAReportedFailure) {
  const VioScene scene(1.0, 1.2, 12);
  // The same frame ten times: no baseline.
  std::vector<CameraFrame> w(10, scene.frames.front());
  const VisualSfmResult r = solve_visual_sfm(bearings(scene, w));
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("parallax"), std::string::npos) << r.message;
  EXPECT_FALSE(solve_visual_sfm({}).success);
}

TEST(VisualInertialStartup, MissingImuIsReported) {
  const VioScene scene(1.0, 3.0, 14);
  const std::vector<CameraFrame> w = window(scene, 0, 10, 3);
  const std::vector<ImuMeasurement> short_imu(scene.imu.begin(), scene.imu.begin() + 50);
  VisualSfmOptions so;
  so.focal_px = 300.0;
  const InitializerResult r = initialize_from_frames(w, short_imu, *scene.camera, scene.T_imu_cam, scene.noise, so);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("IMU"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace slamkit
