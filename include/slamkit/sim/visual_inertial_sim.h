// Visual-inertial simulator: replays a real motion (a BSplineTrajectory of the IMU/body frame)
// through a simulated IMU and camera looking at a room of static landmarks and at moving
// rigid landmark groups ("people" walking through), with tracked features and ground truth.
//
// World: the trajectory's frame, z up, gravity g_world = (0, 0, −gravity).
// IMU at imu_rate (200 Hz) at t_k = t_start + k / imu_rate:
//   ω_m = ω_body(t) + b_g + n_g,   a_m = R(t)ᵀ (p̈(t) − g_world) + b_a + n_a,
//   n ~ N(0, σ_density² · imu_rate) per axis (continuous density → discrete std σ·√f),
//   b_{k+1} = b_k + σ_walk · √Δt · N(0, I)  (bias random walk), b_0 ~ N(0, σ_b0²).
// Camera at imu_rate / imu_per_frame (20 Hz) at every imu_per_frame-th IMU time (so every
// frame time is an IMU time), pose T_world_cam = T_world_imu · T_cam_imu⁻¹.
// Landmarks: points on the walls, floor and ceiling of a box around the path
// (wall_margin beyond the path's bounding box), and moving groups: rigid clusters of 20–50
// points on a person-sized box (0.5 × 0.3 × 1.75 m) walking on a straight line at 0.5–1.5 m/s
// across the camera's view (crossing its horizontal viewing direction at the middle of the
// window, clamped to stay 0.3 m inside the walls), active in [t_on, t_off] for up to 5–10 s
// (cut to the time the walk stays inside the room). Levels (options below): none (no groups), low
// (0.9 groups active on average, passing 2–5 m in front), high (a crowd: 8 active on average,
// passing 0.6–1.5 m in front).
// A landmark is visible if it is 0.1–max_depth m in front (z_cam > 0), projects inside the
// image (border_px), inside the fisheye mask circle (mask_radius_px around the principal
// point, 0 = no mask), its group is active, and the segment from the camera to it does not
// pass through an active person box (people hide the walls and their own far side).
// Tracking: a visible landmark tracked in the previous frame keeps its track id (unless lost
// with track_loss_probability, as a KLT tracker loses tracks); the frame is then filled up to
// features_per_frame with new tracks of visible landmarks at least min_feature_distance_px
// from the kept ones (moving-group points first, dynamic_detection_priority). Observed pixels get N(0, pixel_noise_sigma²) noise per axis.
// Deterministic for a given seed (separate random streams for the world, the IMU and the
// tracker, so the static world and the IMU noise do not change with the dynamic level).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/geometry/se3.h"
#include "slamkit/sim/bspline_trajectory.h"

namespace slamkit {

enum class DynamicLevel { kNone, kLow, kHigh };
const char* to_string(DynamicLevel level);
/// "none" | "low" | "high"; anything else throws InputError (field "dynamic").
DynamicLevel parse_dynamic_level(const std::string& text);

/// Continuous-time IMU noise; the defaults are TUM-VI's (../shared/datasets/vio/README.md).
struct ImuNoiseDensities {
  double gyro_noise_density = 0.00016;   ///< rad/s/√Hz
  double gyro_random_walk = 2.2e-5;      ///< rad/s²/√Hz
  double accel_noise_density = 0.0028;   ///< m/s²/√Hz
  double accel_random_walk = 0.00086;    ///< m/s³/√Hz
};

struct VisualInertialSimOptions {
  std::uint64_t seed = 1;
  DynamicLevel dynamic = DynamicLevel::kNone;
  double imu_rate = 200.0;    ///< Hz
  int imu_per_frame = 10;     ///< camera rate = imu_rate / imu_per_frame (20 Hz)
  ImuNoiseDensities imu_noise;
  double initial_gyro_bias_sigma = 0.002;  ///< rad/s, std of b_g(0) per axis
  double initial_accel_bias_sigma = 0.02;  ///< m/s², std of b_a(0) per axis
  double gravity = 9.81;                   ///< m/s²
  double pixel_noise_sigma = 1.0;          ///< px
  int features_per_frame = 150;
  double min_feature_distance_px = 20.0;
  double border_px = 2.0;
  double mask_radius_px = 0.0;       ///< fisheye mask circle around (cx, cy); 0: no mask
  double max_depth = 20.0;           ///< m
  double track_loss_probability = 0.01;
  /// New tracks start on visible points of moving groups before static ones (people are
  /// textured: a corner detector fires on them), so a crowd takes over the feature budget.
  bool dynamic_detection_priority = true;
  double wall_margin = 1.5;          ///< m beyond the path's bounding box (horizontal)
  double floor_below = 1.2;          ///< m below the lowest path point
  double ceiling_above = 1.0;        ///< m above the highest path point
  double landmark_density = 12.0;    ///< static landmarks per m² of wall, floor and ceiling
  double duration = 0.0;             ///< s from the spline's start; 0: the whole spline
  /// Mean number of active moving groups (each active 5–10 s) and their passing distance in
  /// front of the camera [m], per level.
  double concurrent_groups_low = 0.9, concurrent_groups_high = 8.0;
  double passing_low_min = 2.0, passing_low_max = 5.0;
  double passing_high_min = 0.6, passing_high_max = 1.5;
};

/// True IMU/body state at one time.
struct SimState {
  double t = 0.0;
  Eigen::Vector3d p_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_imu = Eigen::Quaterniond::Identity();
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();  ///< accelerometer bias [m/s²]
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();  ///< gyroscope bias [rad/s]
};

struct SimImuSample {
  double t = 0.0;
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   ///< rad/s, IMU frame
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  ///< m/s², specific force, IMU frame
};

struct SimObservation {
  std::int64_t track_id = 0;
  std::int64_t landmark_id = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< noisy pixel
  bool dynamic = false;                          ///< label: the landmark belongs to a moving group
  /// false: the front end has not tested the track yet (a new track on images); the simulator's
  /// labels are always known.
  bool classified = true;
};

struct SimFrame {
  double t = 0.0;
  std::size_t imu_index = 0;  ///< imu[imu_index].t == t
  SimState truth;             ///< == imu_truth[imu_index]
  std::vector<SimObservation> observations;
};

/// A landmark: static (group −1, position in the world) or a point of a moving group
/// (position in the group's body frame).
struct SimLandmark {
  std::int64_t id = 0;
  int group = -1;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// A rigid group walking on a straight line: T_world_group(t) = (Rz(yaw), start + velocity·(t − t_on)),
/// present for t ∈ [t_on, t_off].
struct SimMovingGroup {
  int id = 0;
  double t_on = 0.0, t_off = 0.0;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  bool active(double t) const { return t >= t_on && t <= t_off; }
  SE3 pose(double t) const;
};

/// A simulated run: what a VIO estimator consumes (camera, IMU, observations) and the truth.
struct VisualInertialSim {
  std::string source;  ///< e.g. "room1", "euroc:V1_01", a file name
  std::uint64_t seed = 0;
  DynamicLevel dynamic = DynamicLevel::kNone;
  std::shared_ptr<CameraModel> camera;
  SE3 T_cam_imu;
  double mask_radius_px = 0.0;
  ImuNoiseDensities imu_noise;
  double imu_rate = 200.0;
  Eigen::Vector3d gravity_world = Eigen::Vector3d(0.0, 0.0, -9.81);
  double pixel_noise_sigma = 1.0;
  std::vector<SimLandmark> landmarks;
  std::vector<SimMovingGroup> groups;
  std::vector<SimImuSample> imu;
  std::vector<SimState> imu_truth;  ///< one per IMU sample, same times
  std::vector<SimFrame> frames;

  /// World position of a landmark at time t (moving groups follow their path).
  Eigen::Vector3d landmark_world(const SimLandmark& l, double t) const;
};

/// Summary numbers of a run.
struct SimSummary {
  double duration = 0.0;  ///< s
  std::size_t frames = 0, imu_samples = 0, static_landmarks = 0, dynamic_landmarks = 0, groups = 0;
  double features_per_frame_mean = 0.0;
  std::size_t features_per_frame_min = 0;
  double dynamic_share = 0.0;        ///< dynamic observations / all observations
  double static_ratio_min = 1.0;     ///< min over frames of M = static / all
  double static_ratio_mean = 1.0;    ///< mean over frames of M
  std::size_t frames_static_below_half = 0;  ///< frames with M < 0.5
  std::size_t frames_static_below_07 = 0;    ///< frames with M < 0.7
  std::size_t frames_static_below_09 = 0;    ///< frames with M < 0.9
  std::size_t frames_with_dynamic = 0;
  double mean_track_length = 0.0;    ///< frames per track
  std::size_t tracks = 0;
};
SimSummary summarize(const VisualInertialSim& sim);

/// Runs the simulator over [spline start, spline start + duration]. Throws std::invalid_argument
/// on unusable options (rates, counts) or a camera that is missing.
VisualInertialSim simulate_visual_inertial(const BSplineTrajectory& trajectory, std::shared_ptr<CameraModel> camera,
                                           const SE3& T_cam_imu, const VisualInertialSimOptions& options);

}  // namespace slamkit
