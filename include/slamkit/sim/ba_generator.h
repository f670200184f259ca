// Synthetic bundle-adjustment problems in the BAL camera model (core/bal_problem.h), for
// measuring scaling beyond the real BAL files: `sim:ba?cameras=N&points=M&seed=S`.
//
// Cameras drive along a straight street (x axis, `spacing` apart) looking sideways at a
// facade-like volume (+y, depth 4–20), with small random yaw/pitch/roll, f ≈ 500 px and mild
// radial distortion. Each point is made in the view of a random anchor camera and observed by
// a run of `min_track`..`max_track` consecutive cameras around it (those that see it in front
// and inside the 1000×750 px image), so S has a banded, realistic sparsity. Observations get
// Gaussian pixel noise (σ = noise px); the start perturbs rotations, centres, focal lengths
// and points. Generation is O(points · max_track) and deterministic for a seed.
#pragma once

#include <cstdint>
#include <string>

#include "slamkit/core/bal_problem.h"

namespace slamkit {

struct BaSimOptions {
  int cameras = 200;
  int points = 20000;
  std::uint64_t seed = 1;
  double noise = 1.0;           ///< pixel noise σ
  int min_track = 2, max_track = 8;
  double spacing = 0.5;         ///< distance between cameras
  double rotation_start_sigma = 2e-3, centre_start_sigma = 0.05, point_start_sigma = 0.1, focal_start_sigma = 2.0;
};

/// The noisy problem with a perturbed start; `truth` (optional) gets the true cameras/points
/// with the same observations. Throws InputError for sizes out of range.
BalProblem generate_ba_problem(const BaSimOptions& options, BalProblem* truth = nullptr);

/// "sim:ba", "sim:ba?cameras=2000&points=500000&seed=3" (also noise, min_track, max_track):
/// true if spec names a generated BA problem; fills options. Throws InputError on a bad key/value.
bool parse_ba_sim_spec(const std::string& spec, BaSimOptions* options);

}  // namespace slamkit
