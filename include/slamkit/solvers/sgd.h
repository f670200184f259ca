// SGD: stochastic gradient descent on pose graphs (Olson, Leonard, Teller, ICRA 2006).
//
// Parameterization: incremental poses along the odometry chain (vertex ids in order), in the
// global frame, x_k = x_{k−1} + p_k. One update visits one constraint a → b, computes its
// global-frame residual r and information W = G Ω Gᵀ, and changes the increments on the chain
// between a and b by β = clamp(l · α · 2 W r, |r|) split in proportion to 1/M (M: the diagonal
// of JᵀWJ, the preconditioner), with the learning rate α = 1/(γ · t) decreasing with the
// iteration t (γ: the smallest diagonal information). Constraints are visited in file order
// in the first iterations, then in a random order (seeded, so the run is deterministic).
// Cost of an update: 2D O(log N) (sgd_chain_2d.h), 3D O(path length + depth) = O(N) on the
// chain. 3D uses the rotation/translation split of the TORO engine on the same
// chain. Converges from the odometry guess and, in 2D, from all-zero poses. In 2D a second
// phase (gradient_phase, relaxer.h) takes over when this update stalls: one common learning
// rate and the full Jacobian (θ–translation coupling), whose fixed point is the optimum.
#pragma once

#include <cstdint>

#include "slamkit/solvers/relaxer.h"

namespace slamkit {

struct SgdOptions {
  RelaxerStop stop;
  /// 2D: the unbiased second phase (relaxer.h). On the chain the paths are long, so SGD takes
  /// a low quantile of the path-length factors (measured on M3500 and INTEL).
  RelaxerGradientPhase gradient_phase = sgd_gradient_phase();
  static RelaxerGradientPhase sgd_gradient_phase() {
    RelaxerGradientPhase p;
    p.quantile = 0.1;
    return p;
  }
  std::uint64_t seed = 1;  ///< order of the constraints in each iteration
  bool shuffle = true;     ///< false: file order in every iteration
  /// The first `file_order_iterations` iterations visit the constraints in file order (Olson's
  /// Algorithm 1 loops over the constraint list), the later ones in the seeded random order.
  /// With α = 1/(γ t) the first iterations satisfy nearly every constraint in full (β clamped
  /// to r), one after the other, so their order decides the basin: in the file's time order the
  /// chain is rebuilt like an online map (M3500 from all-zero poses and M3500b then end in the
  /// optimum's basin; from the random order they do not). The random order afterwards is faster.
  int file_order_iterations = 3;
};

/// Optimizes the poses of `g` in place. Throws InputError for graphs the relaxers cannot take
/// (landmarks, disconnected, singular information; see make_relaxer_graph).
RelaxerSummary optimize_sgd(PoseGraph& g, const SgdOptions& options = {});

}  // namespace slamkit
