// TORO: tree-based network optimizer (Grisetti, Stachniss, Grzonka, Burgard, RSS 2007; 3D:
// Grisetti et al., ICRA 2008).
//
// Parameterization: each pose relative to its parent in a breadth-first spanning tree rooted
// at the gauge (2D: global-frame increments, 3D: relative motions x_parent⁻¹ x_k). One update
// visits a constraint a → b and distributes its residual along the tree path a … top … b
// (top: the lowest common ancestor), each node's share ∝ 1/M_k; the constraints are visited
// in order of increasing path length. 2D: one preconditioned step per constraint as in SGD,
// with W rotated into the global frame. 3D: first the rotational residual is spread as
// fractional rotations about one global axis, then the translational residual as cumulative
// shifts (the rotation/translation split), each scaled by a learning rate 1/(γ · t) and
// clamped so that no update overshoots. Cost of an update: O(path length + tree depth), which
// the spanning tree keeps short. 2D: the same second phase as SGD (gradient_phase, relaxer.h),
// visiting the constraints in a seeded random order.
#pragma once

#include <cstdint>

#include "slamkit/solvers/relaxer.h"

namespace slamkit {

struct ToroOptions {
  RelaxerStop stop;
  RelaxerGradientPhase gradient_phase;  ///< 2D: the unbiased second phase (relaxer.h)
  /// The papers' update (and 3D) visits the constraints shortest path first; the 2D gradient phase (a
  /// stochastic gradient with one common learning rate) in a random order drawn from `seed`
  /// in every iteration, which removes the bias of a fixed cyclic order at a finite step
  /// (measured on INTEL: 235.7 after 4000 iterations, 240 in the sorted order).
  bool shuffle_in_gradient_phase = true;
  std::uint64_t seed = 1;
};

/// Optimizes the poses of `g` in place. Throws InputError for graphs the relaxers cannot take.
RelaxerSummary optimize_toro(PoseGraph& g, const ToroOptions& options = {});

}  // namespace slamkit
