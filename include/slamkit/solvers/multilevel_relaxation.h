// Multi-level relaxation (Frese, Larsson, Duckett, IEEE T-RO 2005): the relaxation of
// gauss_seidel_relaxation.h accelerated by multigrid. Each iteration linearizes all
// constraints at the current poses (H δ = −g in the right-perturbation tangent spaces) and
// solves that system approximately with V-cycles: block Gauss-Seidel smoothing on the fine
// level, the residual restricted to a coarser graph in which consecutive poses are merged in
// pairs, recursively down to a few nodes solved directly, the coarse correction prolongated
// back and smoothed again. Restriction/prolongation P move a merged group rigidly with its
// representative pose (block Ad(Y⁻¹), Y = x_rep⁻¹ x_k), and the coarse matrices are Galerkin
// products Pᵀ H P, so a coarse level is the same kind of pose graph. Then x ← x ⊞ δ.
// Cost of a V-cycle: O(E D² + N D³) summed over the log₂ N levels, i.e. linear in the graph.
#pragma once

#include "slamkit/solvers/relaxer.h"

namespace slamkit {

struct MultilevelOptions {
  RelaxerStop stop;
  int pre_smoothing = 2;     ///< Gauss-Seidel sweeps before restricting
  int post_smoothing = 2;    ///< after prolongating
  int max_cycles = 20;       ///< V-cycles per linearization
  double cycle_tolerance = 1e-3;  ///< stop the cycles when ‖r‖ ≤ this · ‖g‖
  int coarsest_nodes = 32;   ///< solve directly at or below this many nodes
};

RelaxerSummary optimize_multilevel(PoseGraph& g, const MultilevelOptions& options = {});

}  // namespace slamkit
