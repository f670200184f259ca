// 2D landmark-world simulator (the Bailey/Nieto consistency benchmark setup).
// Vehicle: bicycle model x' = x + v dt cos(θ+G), y' = y + v dt sin(θ+G), θ' = θ + v dt sin(G)/L,
// steering G toward the next waypoint with a proportional gain, a steering limit and a rate
// limit. The filter receives (v, G) corrupted by N(0, σ_v²), N(0, σ_G²); the sensor returns
// (range, bearing) of every landmark within max_range every `observe_every` control steps.
// Everything is drawn from one seeded generator, so a (world, options, seed) triple gives the
// same noise draws to every filter that consumes the run.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "slamkit/filters/models.h"  // BicycleModel (the true motion), RangeBearing

namespace slamkit {

struct LandmarkSimOptions {
  double wheelbase = 4.0;          // m
  double speed = 3.0;              // m/s
  double dt = 0.025;               // s, control step
  double steer_gain = 5.0;         // G rate toward the waypoint heading error
  double max_steer = 30.0 * 3.14159265358979323846 / 180.0;  // rad
  double max_steer_rate = 20.0 * 3.14159265358979323846 / 180.0;  // rad/s
  double waypoint_radius = 1.0;    // m, distance at which a waypoint counts as reached
  int laps = 1;                    // closed route: laps over the waypoint list
  int max_steps = 0;               // 0: until the last waypoint of the last lap
  double sigma_v = 0.3;            // m/s
  double sigma_steer = 3.0 * 3.14159265358979323846 / 180.0;  // rad
  int observe_every = 8;           // control steps between observations (0.2 s)
  double max_range = 30.0;         // m
  double min_range = 0.5;          // m: closer landmarks are inside the vehicle, not observed
                                   // (keeps noisy ranges positive and bearings defined)
  double sigma_range = 0.1;        // m
  double sigma_bearing = 1.0 * 3.14159265358979323846 / 180.0;  // rad
};

struct LandmarkSimStep {
  Eigen::Vector3d true_pose;        // after this control
  double v = 0, steer = 0;          // noisy control the filter sees
  bool observed = false;
  std::vector<RangeBearing> observations;
};

struct LandmarkSimRun {
  std::vector<LandmarkSimStep> steps;
};

/// Simulates one run from pose (0,0,0). Throws InputError on empty waypoints or bad options.
LandmarkSimRun simulate_landmark_run(const std::vector<Eigen::Vector2d>& landmarks,
                                     const std::vector<Eigen::Vector2d>& waypoints,
                                     const LandmarkSimOptions& options, std::uint64_t seed);

/// A survey scan: noisy range-bearing observations of every landmark seen from `pose` with no
/// range limit (the options' noise and min_range), from its own seeded generator. Given as the
/// first update, it puts the whole world into the map at once, so a benchmark times a filter's
/// step at exactly N landmarks without driving the route that would discover them.
std::vector<RangeBearing> survey_scan(const std::vector<Eigen::Vector2d>& landmarks, const Eigen::Vector3d& pose,
                                      const LandmarkSimOptions& options, std::uint64_t seed);

/// A generated world: `num_waypoints` waypoints on a circle of radius `radius` (a closed
/// route) and N landmarks placed uniformly in a band of ±band metres around the route.
void generate_landmark_world(int num_landmarks, std::uint64_t seed,
                             std::vector<Eigen::Vector2d>* landmarks,
                             std::vector<Eigen::Vector2d>* waypoints, double radius = 0,
                             double band = 20.0, int num_waypoints = 24);

}  // namespace slamkit
