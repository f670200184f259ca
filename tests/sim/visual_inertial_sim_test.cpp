// Visual-inertial simulator: IMU measurements integrate back to the true motion, noise has
// the configured discrete std, every observation reprojects from the truth, tracks keep
// their landmark, labels match the groups, dynamic levels order, seeds reproduce.
#include "slamkit/sim/visual_inertial_sim.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "slamkit/io/trajectory_io.h"
#include "testing/data.h"
#include "testing/tumvi_rig.h"

namespace slamkit {
namespace {

using testing::tumvi_camera;
using testing::tumvi_T_cam_imu;
using testing::circle_path;

VisualInertialSimOptions noise_free() {
  VisualInertialSimOptions o;
  o.imu_noise = ImuNoiseDensities{0, 0, 0, 0};
  o.initial_accel_bias_sigma = o.initial_gyro_bias_sigma = 0.0;
  o.pixel_noise_sigma = 0.0;
  return o;
}

TEST(VisualInertialSim, NoiseFreeImuIntegratesToTheTruth) {
  const BSplineTrajectory spline = circle_path();
  const VisualInertialSim sim = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), noise_free());
  ASSERT_EQ(sim.imu.size(), sim.imu_truth.size());
  // Midpoint integration over 1 s (200 steps) from the true state at 5 s.
  const std::size_t k0 = 1000, steps = 200;
  SO3 R(sim.imu_truth[k0].q_world_imu);
  Eigen::Vector3d v = sim.imu_truth[k0].v_world, p = sim.imu_truth[k0].p_world;
  for (std::size_t k = k0; k < k0 + steps; ++k) {
    const double dt = sim.imu[k + 1].t - sim.imu[k].t;
    const Eigen::Vector3d w = 0.5 * (sim.imu[k].gyro + sim.imu[k + 1].gyro);
    const SO3 R1 = R * SO3::exp(w * dt);
    const Eigen::Vector3d a = 0.5 * (R.act(sim.imu[k].accel) + R1.act(sim.imu[k + 1].accel)) + sim.gravity_world;
    p += v * dt + 0.5 * a * dt * dt;
    v += a * dt;
    R = R1;
  }
  const SimState& truth = sim.imu_truth[k0 + steps];
  EXPECT_LT((p - truth.p_world).norm(), 2e-3);
  EXPECT_LT((v - truth.v_world).norm(), 5e-3);
  EXPECT_LT(SO3(truth.q_world_imu).between(R).log().norm(), 1e-4);
}

TEST(VisualInertialSim, ImuNoiseHasTheDiscreteStd) {
  const BSplineTrajectory spline = circle_path();
  VisualInertialSimOptions o;
  o.imu_noise.gyro_random_walk = o.imu_noise.accel_random_walk = 0.0;  // constant biases
  const VisualInertialSim sim = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o);
  const VisualInertialSim clean = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), noise_free());
  double sg = 0, sa = 0;
  for (std::size_t k = 0; k < sim.imu.size(); ++k) {
    sg += (sim.imu[k].gyro - clean.imu[k].gyro - sim.imu_truth[k].b_g).squaredNorm();
    sa += (sim.imu[k].accel - clean.imu[k].accel - sim.imu_truth[k].b_a).squaredNorm();
  }
  const double n = 3.0 * sim.imu.size();
  EXPECT_NEAR(std::sqrt(sg / n), 0.00016 * std::sqrt(200.0), 0.03 * 0.00016 * std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(sa / n), 0.0028 * std::sqrt(200.0), 0.03 * 0.0028 * std::sqrt(200.0));
}

TEST(VisualInertialSim, BiasRandomWalkGrowsLikeSqrtTime) {
  const BSplineTrajectory spline = circle_path();
  VisualInertialSimOptions o;
  o.initial_gyro_bias_sigma = o.initial_accel_bias_sigma = 0.0;
  // Increments of b_a over 1 s across 40 seeds: std ≈ σ_walk · √1 s.
  double ss = 0;
  int n = 0;
  for (int seed = 1; seed <= 40; ++seed) {
    o.seed = seed;
    o.duration = 2.0;
    const VisualInertialSim sim = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o);
    ss += (sim.imu_truth[200].b_a - sim.imu_truth[0].b_a).squaredNorm();
    n += 3;
  }
  EXPECT_NEAR(std::sqrt(ss / n), 0.00086, 0.25 * 0.00086);
}

TEST(VisualInertialSim, ObservationsReprojectTracksAndLabelsAreConsistent) {
  const BSplineTrajectory spline = circle_path();
  VisualInertialSimOptions o;
  o.dynamic = DynamicLevel::kHigh;
  o.mask_radius_px = 300.0;
  const VisualInertialSim sim = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o);
  ASSERT_EQ(sim.frames.size(), 401u);  // 20 s at 20 Hz, both ends
  std::map<std::int64_t, std::int64_t> landmark_of_track;
  std::map<std::int64_t, std::size_t> last_frame_of_track;
  double worst = 0.0;
  for (std::size_t f = 0; f < sim.frames.size(); ++f) {
    const SimFrame& frame = sim.frames[f];
    EXPECT_EQ(frame.t, sim.imu[frame.imu_index].t);
    EXPECT_EQ(frame.imu_index, 10 * f);
    EXPECT_LE(frame.observations.size(), 150u);
    const SE3 T_world_cam = SE3(SO3(frame.truth.q_world_imu), frame.truth.p_world) * sim.T_cam_imu.inverse();
    for (const SimObservation& obs : frame.observations) {
      const SimLandmark& l = sim.landmarks.at(static_cast<std::size_t>(obs.landmark_id));
      EXPECT_EQ(obs.dynamic, l.group >= 0);
      if (l.group >= 0) EXPECT_TRUE(sim.groups[static_cast<std::size_t>(l.group)].active(frame.t));
      Eigen::Vector2d uv;
      const Eigen::Vector3d pc = T_world_cam.inverse().act(sim.landmark_world(l, frame.t));
      ASSERT_GT(pc.z(), 0.0);
      ASSERT_TRUE(sim.camera->project(pc, &uv));
      worst = std::max(worst, (uv - obs.uv).cwiseAbs().maxCoeff());
      EXPECT_LT((uv - Eigen::Vector2d(254.93, 256.90)).norm(), 300.0 + 1e-9);
      const auto [it, fresh] = landmark_of_track.emplace(obs.track_id, obs.landmark_id);
      EXPECT_EQ(it->second, obs.landmark_id) << "track " << obs.track_id << " changed landmark";
      // A track is continuous: it is seen in consecutive frames only.
      if (!fresh) EXPECT_EQ(last_frame_of_track[obs.track_id], f - 1) << "track " << obs.track_id << " resumed";
      last_frame_of_track[obs.track_id] = f;
    }
  }
  // People walk inside the room (the box of the static landmarks).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const SimLandmark& l : sim.landmarks)
    if (l.group < 0) lo = lo.cwiseMin(l.position), hi = hi.cwiseMax(l.position);
  ASSERT_FALSE(sim.groups.empty());
  for (const SimMovingGroup& g : sim.groups)
    for (const double t : {g.t_on, g.t_off}) {
      const Eigen::Vector3d p = g.pose(t).translation();
      EXPECT_TRUE(p.x() >= lo.x() && p.x() <= hi.x() && p.y() >= lo.y() && p.y() <= hi.y()) << p.transpose();
      EXPECT_NEAR(p.z(), lo.z(), 1e-9);
    }
  EXPECT_LT(worst, 6.0);  // 1 px noise: 6σ
  EXPECT_GT(worst, 2.0);  // and there is noise
  const SimSummary s = summarize(sim);
  EXPECT_GT(s.features_per_frame_mean, 120.0);  // the crowd hides part of the room
  EXPECT_GT(s.mean_track_length, 10.0);
  EXPECT_GT(s.dynamic_share, 0.0);
}

TEST(VisualInertialSim, DynamicLevelsOrderAndSeedsReproduce) {
  const BSplineTrajectory spline = circle_path();
  VisualInertialSimOptions o;
  const auto share = [&](DynamicLevel level, std::uint64_t seed) {
    o.dynamic = level;
    o.seed = seed;
    return summarize(simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o));
  };
  const SimSummary none = share(DynamicLevel::kNone, 1), low = share(DynamicLevel::kLow, 1),
                   high = share(DynamicLevel::kHigh, 1);
  std::printf("dynamic share: none %.3f, low %.3f, high %.3f (high: static ratio M min %.2f, mean %.2f, "
              "%zu of %zu frames with M < 0.5)\n", none.dynamic_share, low.dynamic_share, high.dynamic_share,
              high.static_ratio_min, high.static_ratio_mean, high.frames_static_below_half, high.frames);
  EXPECT_EQ(none.dynamic_share, 0.0);
  EXPECT_EQ(none.groups, 0u);
  EXPECT_GT(low.dynamic_share, 0.0);
  EXPECT_GT(high.dynamic_share, 2.0 * low.dynamic_share);
  EXPECT_EQ(none.static_landmarks, high.static_landmarks);  // same room for every level
  o.dynamic = DynamicLevel::kLow;
  o.seed = 9;
  const VisualInertialSim a = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o);
  const VisualInertialSim b = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o);
  o.seed = 10;
  const VisualInertialSim c = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), o);
  EXPECT_EQ(a.imu[77].accel, b.imu[77].accel);
  EXPECT_EQ(a.frames[50].observations[3].uv, b.frames[50].observations[3].uv);
  EXPECT_NE(a.imu[77].accel, c.imu[77].accel);
}

TEST(VisualInertialSim, TumViRoom1HasAbout150FeaturesPerFrame) {
  SLAMKIT_REQUIRE_DATA(file, "vio/tumvi/gt/dataset-room1_512_16.csv");
  const Trajectory gt = read_trajectory(file.string(), TrajectoryFormat::kEuroc);
  Trajectory head;
  for (const auto& s : gt)
    if (s.stamp < gt[0].stamp + 30.0) head.push_back(s);
  VisualInertialSimOptions o;
  o.mask_radius_px = 300.0;
  o.dynamic = DynamicLevel::kLow;
  const VisualInertialSim sim =
      simulate_visual_inertial(BSplineTrajectory::fit(head), tumvi_camera(), tumvi_T_cam_imu(), o);
  const SimSummary s = summarize(sim);
  std::printf("room1 30 s: %zu frames, %.1f features/frame (min %zu), tracks %.1f frames long, dynamic share %.3f\n",
              s.frames, s.features_per_frame_mean, s.features_per_frame_min, s.mean_track_length, s.dynamic_share);
  EXPECT_GT(s.features_per_frame_mean, 140.0);
  EXPECT_GT(s.features_per_frame_min, 60u);
}

}  // namespace
}  // namespace slamkit
