// The VIO start-up without ground truth, end to end on a short simulated run (TUM-VI fisheye
// and IMU noise, a handheld-like path made here, no dataset needed): the visual SfM window and
// the visual-inertial alignment must succeed, with small scale, gravity and velocity errors,
// and the run that follows must stay accurate; a run too short to initialize is a clear
// InputError, and a run whose IMU goes back in time is one too.
#include <gtest/gtest.h>

#include <cmath>

#include "slamkit/core/error.h"
#include "slamkit/vio/vio_sim_runner.h"
#include "testing/tumvi_rig.h"

namespace slamkit {
namespace {

using testing::tumvi_camera;
using testing::tumvi_T_cam_imu;

// A handheld walk: a 2 m circle at 1.4 m with vertical and radial sway (≈ 0.5 m/s² of
// acceleration changes, as a person carrying the sensor gives) and swaying rotation.
VisualInertialSim handheld_run(double duration, std::uint64_t seed, DynamicLevel dynamic = DynamicLevel::kNone) {
  Trajectory path;
  for (double t = 0.0; t <= duration + 1.0; t += 0.01) {
    const double a = 0.4 * t, r = 2.0 + 0.12 * std::sin(1.9 * t);
    const Eigen::Vector3d p(r * std::cos(a), r * std::sin(a), 1.4 + 0.12 * std::sin(2.3 * t));
    const SO3 R = SO3::exp(Eigen::Vector3d(0, 0, a + M_PI)) * SO3::exp(Eigen::Vector3d(0.2 * std::sin(0.7 * t), 0.1, 0));
    path.push_back(t, SE3(R, p));
  }
  VisualInertialSimOptions o;
  o.seed = seed;
  o.duration = duration;
  o.mask_radius_px = 300.0;
  o.dynamic = dynamic;
  VisualInertialSim sim = simulate_visual_inertial(BSplineTrajectory::fit(path), tumvi_camera(), tumvi_T_cam_imu(), o);
  sim.source = "handheld test run";
  return sim;
}

TEST(VioStartup, InitializesWithoutGroundTruthAndTracks) {
  const VisualInertialSim sim = handheld_run(8.0, 3);
  const VioRunResult r = run_vio_on_sim(sim, SlidingWindowOptions{});
  const VioStartupReport& s = r.startup;
  EXPECT_EQ(s.method, "visual-inertial initializer");
  EXPECT_GE(s.attempts, 1);
  EXPECT_EQ(s.window_frames, 10);
  EXPECT_LT(s.scale_error, 0.08) << s.message;  // measured 0.053: 44 inliers in the reference pair
  EXPECT_LT(s.gravity_error_deg, 1.5) << s.message;
  EXPECT_LT(s.velocity_error, 0.15) << s.message;
  EXPECT_LT(s.gyro_bias_error, 0.005) << s.message;
  EXPECT_GT(r.initialized_at_s, 0.0);
  EXPECT_LT(r.initialized_at_s, 4.0);
  EXPECT_EQ(r.estimate.size(), r.truth.size());
  // The run after the start-up: position error (after the same gauge) stays small.
  double worst = 0.0;
  for (std::size_t k = 0; k < r.estimate.size(); ++k) {
    ASSERT_TRUE(r.estimate[k].T_world_body.translation().allFinite());
    worst = std::max(worst, (r.estimate[k].T_world_body.translation() - r.truth[k].T_world_body.translation()).norm());
  }
  EXPECT_LT(worst, 0.25);
}

// With DVI on, the start-up SfM leaves out the observations flagged dynamic (here the simulator's
// labels); the baseline uses them all. Both start, and the report counts what was left out.
TEST(VioStartup, DviStartupLeavesOutDynamicFeatures) {
  const VisualInertialSim sim = handheld_run(8.0, 3, DynamicLevel::kHigh);
  SlidingWindowOptions dvi;
  dvi.dvi.enabled = true;
  const VioRunResult on = run_vio_on_sim(sim, dvi);
  const VioRunResult off = run_vio_on_sim(sim, SlidingWindowOptions{});
  EXPECT_GT(on.startup.dynamic_left_out, 0) << on.startup.message;
  EXPECT_EQ(off.startup.dynamic_left_out, 0);
  EXPECT_LT(on.startup.rotation_rms_deg, 2.0);
  EXPECT_LT(on.startup.scale_error, 0.15) << on.startup.message;
  VioStartupOptions keep;
  keep.dvi_startup = false;
  EXPECT_EQ(run_vio_on_sim(sim, dvi, {}, keep).startup.dynamic_left_out, 0);
}

TEST(VioStartup, GroundTruthStartIsStillAvailable) {
  const VisualInertialSim sim = handheld_run(3.0, 4);
  VioStartupOptions o;
  o.use_ground_truth = true;
  const VioRunResult r = run_vio_on_sim(sim, SlidingWindowOptions{}, {}, o);
  EXPECT_EQ(r.startup.method, "ground truth");
  EXPECT_EQ(r.estimate.size(), r.truth.size());
}

TEST(VioStartup, TooShortToInitializeIsAClearError) {
  const VisualInertialSim sim = handheld_run(1.2, 5);
  try {
    run_vio_on_sim(sim, SlidingWindowOptions{});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too short to initialize"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("handheld test run"), std::string::npos) << e.what();
  }
}

TEST(VioStartup, ImuGoingBackInTimeIsAClearError) {
  VisualInertialSim sim = handheld_run(4.0, 6);
  std::swap(sim.imu[500], sim.imu[501]);
  try {
    run_vio_on_sim(sim, SlidingWindowOptions{});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("imu"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slamkit
