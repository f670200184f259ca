// Synthetic pose graphs with known ground truth, for tests, benchmarks and the CLI's
// built-in default problem ("sim:manhattan", "sim:sphere").
//
//   manhattan (2D)  a random walk on a unit grid (straight, or a ±90° turn), with loop
//                   closures to earlier poses within `loop_radius` (like Olson's M3500)
//   sphere (3D)     `rings` rings of `poses_per_ring` poses on a sphere, driven ring after ring,
//                   with loop closures between neighbouring rings (like g2o's create_sphere)
// Measurements are the true relative poses perturbed by Gaussian noise on the tangent,
// Z = Z_true ⊞ n, n ~ N(0, Σ), Σ = diag(σ_t², σ_t², [σ_t²,] σ_r², ...); the information matrix
// is Σ⁻¹ in each edge's error coordinates (the g2o SE3 error uses q.vec ≈ φ/2: ×4 on rotation).
// Initial estimates are the noisy odometry chain. Deterministic for a given seed.
#pragma once

#include <cstdint>
#include <string>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

struct PoseGraphSimOptions {
  std::string world = "manhattan";  ///< "manhattan" (2D) or "sphere" (3D)
  int num_poses = 2000;             ///< manhattan
  double turn_probability = 0.3;    ///< manhattan: chance of a ±90° turn per step
  double loop_radius = 1.1;         ///< manhattan: close loops to earlier poses this near
  double loop_probability = 0.5;    ///< manhattan: chance to keep each candidate loop closure
  int rings = 30;                   ///< sphere
  int poses_per_ring = 40;          ///< sphere
  double radius = 50.0;             ///< sphere
  double translation_sigma = 0.05;  ///< metres
  double rotation_sigma = 0.01;     ///< radians
  std::uint32_t seed = 1;
};

/// Generates the noisy graph; `ground_truth` (optional) gets the same graph with the true
/// poses as estimates. Throws InputError on an unknown world or non-positive sizes.
PoseGraph generate_pose_graph(const PoseGraphSimOptions& options, PoseGraph* ground_truth = nullptr);

/// Largest graph a spec may ask for (poses; rings × per_ring on the sphere).
constexpr long long kMaxSimPoses = 10'000'000;

/// "sim:manhattan", "sim:sphere" (optionally "sim:sphere?seed=3&rings=20"): true if `spec` names
/// a built-in generated graph; fills `options`. Parameters: seed (0..2^32-1), poses (manhattan
/// only, 2..kMaxSimPoses), rings (≥ 2) and per_ring (≥ 3) (sphere only); every value a whole
/// decimal integer. Anything else throws InputError naming the spec and the parameter.
bool parse_sim_spec(const std::string& spec, PoseGraphSimOptions* options);

/// The spec that parse_sim_spec reads back to the same world, seed and sizes.
std::string to_sim_spec(const PoseGraphSimOptions& options);

}  // namespace slamkit
