// The visual-inertial initializer on synthetic data made here: poses of an analytic motion
// seen by a "visual SfM" in an arbitrary frame c0 at an unknown scale, the IMU (with a gyro
// bias) preintegrated between frames. It must recover scale, gravity, velocities and the gyro
// bias, and report failure (not NaN) on a window without excitation.
#include <gtest/gtest.h>

#include <cmath>

#include "slamkit/vio/visual_inertial_initializer.h"
#include "testing/imu_motion.h"

namespace slamkit {
namespace {

using testing::AnalyticMotion;

struct Window {
  InitializerInput input;
  SO3 R_c0_world;
  std::vector<ImuState> truth;
};

Window make_window(const AnalyticMotion& motion, double t0, int frames, double rate, double true_scale,
                   const ImuBias& bias) {
  Window w;
  const SE3 T_imu_cam(SO3::exp(Eigen::Vector3d(-1.2, 0.0, -1.2)), Eigen::Vector3d(0.05, -0.07, -0.04));
  w.input.p_imu_cam = T_imu_cam.translation();
  const double t_end = t0 + (frames - 1) / rate;
  const std::vector<ImuMeasurement> imu = motion.samples(t0 - 0.1, t_end + 0.1, 200.0, bias);
  // c0 = the first camera frame.
  const SE3 T_w_c0 = motion.state(t0).pose() * T_imu_cam;
  w.R_c0_world = T_w_c0.rotation().inverse();
  for (int k = 0; k < frames; ++k) {
    const double t = t0 + k / rate;
    const ImuState s = motion.state(t, bias);
    w.truth.push_back(s);
    const SE3 T_c0_cam = T_w_c0.inverse() * s.pose() * T_imu_cam;
    w.input.R_c0_body.push_back(w.R_c0_world * s.R);
    w.input.p_c0_cam.push_back(T_c0_cam.translation() / true_scale);
    if (k + 1 < frames) {
      ImuPreintegration p(ImuBias{}, ImuNoise::tumvi());
      p.integrate_between(imu, t, t0 + (k + 1) / rate);
      w.input.imu.push_back(p);
    }
  }
  return w;
}

TEST(VisualInertialInitializer, RecoversScaleGravityVelocitiesAndGyroBias) {
  const AnalyticMotion motion;
  const ImuBias bias{Eigen::Vector3d(0.01, -0.02, 0.015), Eigen::Vector3d::Zero()};
  const double true_scale = 0.37;
  const Window w = make_window(motion, 1.0, 21, 10.0, true_scale, bias);
  const InitializerResult r = initialize_visual_inertial(w.input);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_NEAR(r.scale, true_scale, 0.01 * true_scale);
  EXPECT_LT((r.gyro_bias - bias.gyro).norm(), 1e-3);
  const Eigen::Vector3d g_c0_true = w.R_c0_world.act(motion.gravity);
  EXPECT_LT(std::acos(std::min(1.0, r.gravity_c0.normalized().dot(g_c0_true.normalized()))), 0.5 * kPi / 180);
  for (std::size_t k = 0; k < w.truth.size(); ++k)
    EXPECT_LT((r.velocities_c0[k] - w.R_c0_world.act(w.truth[k].v)).norm(), 0.03) << "frame " << k;
  // World states: gravity-aligned (roll and pitch of the truth), metric relative positions.
  for (std::size_t k = 0; k < w.truth.size(); ++k) {
    const Eigen::Vector3d up_est = r.states[k].R.inverse().act(Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d up_true = w.truth[k].R.inverse().act(Eigen::Vector3d::UnitZ());
    EXPECT_LT((up_est - up_true).norm(), 0.01);
    const double d_est = (r.states[k].p - r.states[0].p).norm(), d_true = (w.truth[k].p - w.truth[0].p).norm();
    EXPECT_NEAR(d_est, d_true, 0.01 + 0.01 * d_true);
  }
}

TEST(VisualInertialInitializer, ReportsFailureWithoutExcitation) {
  AnalyticMotion still;
  still.scale = 0.0;  // at rest: constant specific force, no rotation
  const Window w = make_window(still, 1.0, 21, 10.0, 1.0, ImuBias{});
  const InitializerResult r = initialize_visual_inertial(w.input);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("excitation"), std::string::npos) << r.message;
  EXPECT_TRUE(std::isfinite(r.scale));
  // Too few frames, and inconsistent sizes.
  InitializerInput tiny = make_window(AnalyticMotion{}, 1.0, 3, 10.0, 1.0, ImuBias{}).input;
  EXPECT_FALSE(initialize_visual_inertial(tiny).success);
  tiny.imu.clear();
  EXPECT_FALSE(initialize_visual_inertial(tiny).success);
}

// SfM rotations that are not the camera's (what a visual SfM returns when a crowd moving together
// dominates its window) are refused by the gyroscope check, whatever the alignment would give;
// the true rotations pass with a small reported RMS, and a disabled check lets the wrong ones through.
TEST(VisualInertialInitializer, RefusesSfmRotationsThatDisagreeWithTheGyroscope) {
  const AnalyticMotion motion;
  const ImuBias bias{Eigen::Vector3d(0.004, -0.003, 0.002), Eigen::Vector3d::Zero()};
  const Window w = make_window(motion, 1.0, 15, 5.0, 0.2, bias);
  const InitializerResult good = initialize_visual_inertial(w.input);
  ASSERT_TRUE(good.success) << good.message;
  EXPECT_LT(good.rotation_rms_deg, 0.05);
  EXPECT_NE(good.message.find("rotation RMS"), std::string::npos) << good.message;

  // The crowd: a slow yaw about its own axis instead of the camera's rotations (positions kept).
  InitializerInput crowd = w.input;
  for (std::size_t k = 0; k < crowd.R_c0_body.size(); ++k)
    crowd.R_c0_body[k] = SO3::exp(Eigen::Vector3d(0.0, 0.02 * k, 0.0)) * w.input.R_c0_body[0];
  const InitializerResult bad = initialize_visual_inertial(crowd);
  EXPECT_FALSE(bad.success);
  EXPECT_NE(bad.message.find("disagree with the gyroscope"), std::string::npos) << bad.message;
  EXPECT_GT(bad.rotation_rms_deg, 2.0);
  EXPECT_TRUE(std::isfinite(bad.scale));

  // A rotation error of 1° on one frame is within the default 2° RMS; a tighter bound refuses it.
  InitializerInput nudged = w.input;
  nudged.R_c0_body[5] = nudged.R_c0_body[5] * SO3::exp(Eigen::Vector3d(1.0 * kPi / 180, 0.0, 0.0));
  EXPECT_TRUE(initialize_visual_inertial(nudged).success);
  InitializerOptions tight;
  tight.max_rotation_rms_deg = 0.2;
  EXPECT_FALSE(initialize_visual_inertial(nudged, tight).success);
  InitializerOptions off;
  off.max_rotation_rms_deg = 0.0;
  EXPECT_NEAR(initialize_visual_inertial(crowd, off).rotation_rms_deg, bad.rotation_rms_deg, 1e-9);
}

// SfM positions too noisy to carry the scale (errors up to a sixth of the window's extent, as a
// wrong reference pair gives) are refused with the scale's relative σ above the bound; the
// clean window's σ is a fraction of a percent of the scale.
TEST(VisualInertialInitializer, RefusesAScaleTheWindowDoesNotDetermine) {
  const AnalyticMotion motion;
  const Window w = make_window(motion, 1.0, 15, 5.0, 0.2, ImuBias{});
  const InitializerResult good = initialize_visual_inertial(w.input);
  ASSERT_TRUE(good.success) << good.message;
  EXPECT_LT(good.scale_sigma, 0.01 * good.scale);
  double extent = 0.0;
  for (const auto& p : w.input.p_c0_cam) extent = std::max(extent, (p - w.input.p_c0_cam[0]).norm());
  InitializerInput noisy = w.input;
  std::srand(7);
  for (auto& p : noisy.p_c0_cam) p += extent / 6.0 * Eigen::Vector3d::Random();
  const InitializerResult bad = initialize_visual_inertial(noisy);
  EXPECT_FALSE(bad.success);
  EXPECT_NE(bad.message.find("scale is not determined"), std::string::npos) << bad.message;
  InitializerOptions off;
  off.max_scale_rel_sigma = 0.0;
  const InitializerResult unchecked = initialize_visual_inertial(noisy, off);
  if (unchecked.success) EXPECT_GT(unchecked.scale_sigma, 0.25 * unchecked.scale);
}

}  // namespace
}  // namespace slamkit
