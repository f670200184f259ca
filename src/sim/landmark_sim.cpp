#include "slamkit/sim/landmark_sim.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

// Noisy range-bearing observations of every landmark with min_range ≤ r ≤ max_range of `pose`.
// The caller's distribution is used (it caches every second draw), so runs keep one stream.
std::vector<RangeBearing> observe(const std::vector<Eigen::Vector2d>& landmarks, const Eigen::Vector3d& pose,
                                  const LandmarkSimOptions& o, double max_range, std::mt19937_64& rng,
                                  std::normal_distribution<double>& normal) {
  std::vector<RangeBearing> out;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const Eigen::Vector2d dl = landmarks[i] - pose.head<2>();
    const double r = dl.norm();
    if (r > max_range || r < o.min_range) continue;
    RangeBearing z;
    z.id = static_cast<int>(i);
    z.range = r + o.sigma_range * normal(rng);
    z.bearing = wrap_angle(std::atan2(dl.y(), dl.x()) - pose.z() + o.sigma_bearing * normal(rng));
    out.push_back(z);
  }
  return out;
}

}  // namespace

LandmarkSimRun simulate_landmark_run(const std::vector<Eigen::Vector2d>& landmarks,
                                     const std::vector<Eigen::Vector2d>& waypoints,
                                     const LandmarkSimOptions& o, std::uint64_t seed) {
  if (waypoints.empty()) throw InputError("simulator", 0, "waypoints", "no waypoints");
  if (!(o.dt > 0) || !(o.wheelbase > 0) || o.observe_every < 1 || o.laps < 1)
    throw InputError("simulator", 0, "options", "dt, wheelbase, observe_every, laps must be > 0");
  const BicycleModel vehicle(o.wheelbase, o.sigma_v, o.sigma_steer);  // true motion: noise-free
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  LandmarkSimRun run;
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();
  double steer = 0;
  std::size_t wp = 0;
  int lap = 0;
  const int limit = o.max_steps > 0 ? o.max_steps : 10000000;
  for (int k = 0; k < limit; ++k) {
    // Steer toward the current waypoint: G += clamp(gain·Δθ·dt... ) within rate and limit.
    Eigen::Vector2d d = waypoints[wp] - pose.head<2>();
    if (d.norm() < o.waypoint_radius) {
      if (++wp == waypoints.size()) {
        wp = 0;
        if (++lap == o.laps) break;
      }
      d = waypoints[wp] - pose.head<2>();
    }
    double error = wrap_angle(std::atan2(d.y(), d.x()) - pose.z() - steer);
    double max_delta = o.max_steer_rate * o.dt;
    double delta = std::clamp(o.steer_gain * error * o.dt, -max_delta, max_delta);
    steer = std::clamp(steer + delta, -o.max_steer, o.max_steer);
    pose = vehicle.predict(pose, Control{o.speed, steer, o.dt});
    LandmarkSimStep step;
    step.true_pose = pose;
    step.v = o.speed + o.sigma_v * normal(rng);
    step.steer = steer + o.sigma_steer * normal(rng);
    if ((k + 1) % o.observe_every == 0) {
      step.observed = true;
      step.observations = observe(landmarks, pose, o, o.max_range, rng, normal);
    }
    run.steps.push_back(std::move(step));
  }
  return run;
}

std::vector<RangeBearing> survey_scan(const std::vector<Eigen::Vector2d>& landmarks, const Eigen::Vector3d& pose,
                                     const LandmarkSimOptions& options, std::uint64_t seed) {
  if (!pose.allFinite()) throw InputError("simulator", 0, "survey pose", "not finite");
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  return observe(landmarks, pose, options, std::numeric_limits<double>::infinity(), rng, normal);
}

void generate_landmark_world(int n, std::uint64_t seed, std::vector<Eigen::Vector2d>* landmarks,
                             std::vector<Eigen::Vector2d>* waypoints, double radius, double band,
                             int num_waypoints) {
  if (n < 0 || num_waypoints < 3) throw InputError("generated", 0, "N", "need N >= 0 and >= 3 waypoints");
  // Default radius keeps the density near webmap's (~35 landmarks on a 600 m loop).
  if (radius <= 0) radius = std::max(30.0, 3.0 * n / (2 * 3.14159265358979323846) * 0.5);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  waypoints->clear();
  for (int i = 1; i <= num_waypoints; ++i) {
    double a = 2 * 3.14159265358979323846 * i / num_waypoints;
    // Circle through the origin, starting tangent to the x axis.
    waypoints->emplace_back(radius * std::sin(a), radius * (1 - std::cos(a)));
  }
  landmarks->clear();
  for (int i = 0; i < n; ++i) {
    double a = 2 * 3.14159265358979323846 * u(rng);
    double r = radius + band * (2 * u(rng) - 1);
    landmarks->emplace_back(r * std::sin(a), radius - r * std::cos(a));
  }
}

}  // namespace slamkit
