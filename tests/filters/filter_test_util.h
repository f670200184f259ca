// Shared setup of the filter tests: a small simulated world and a run of a filter over it.
#pragma once

#include <memory>

#include "slamkit/filters/landmark_filter.h"
#include "slamkit/sim/landmark_sim.h"

namespace slamkit::testing {

struct SmallWorld {
  std::vector<Eigen::Vector2d> landmarks, waypoints;
  LandmarkSimOptions sim;
  LandmarkFilterOptions filter;
};

inline SmallWorld small_world(int n_landmarks, int steps, std::uint64_t world_seed = 4, double radius = 0) {
  SmallWorld w;
  generate_landmark_world(n_landmarks, world_seed, &w.landmarks, &w.waypoints, radius);
  w.sim.max_steps = steps;
  w.filter.motion = std::make_shared<BicycleModel>(w.sim.wheelbase, w.sim.sigma_v, w.sim.sigma_steer);
  w.filter.sensor = RangeBearingModel(w.sim.sigma_range, w.sim.sigma_bearing);
  return w;
}

/// Feeds one simulated run to the filter; calls after(k) after every step.
template <class After>
void run_filter(LandmarkFilter* f, const LandmarkSimRun& run, const LandmarkSimOptions& sim, After after) {
  for (std::size_t k = 0; k < run.steps.size(); ++k) {
    const auto& s = run.steps[k];
    f->predict(Control{s.v, s.steer, sim.dt});
    if (s.observed) f->update(s.observations);
    after(k);
  }
}

}  // namespace slamkit::testing
