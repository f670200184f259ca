// Relaxation (Duckett, Marsland, Shapiro 2000; Howard, Matarić, Sukhatme 2001): nonlinear
// Gauss-Seidel sweeps. Each pose in turn is re-solved from its neighbours' constraints with
// the neighbours held fixed: one Gauss-Newton step on its own D×D system
//     (Σ_e Jᵀ Ω_e J) δ = −Σ_e Jᵀ Ω_e e,   x ← x ⊞ ω·δ
// (e, J: the g2o error of each incident edge and its Jacobian for this pose; ω the
// over-relaxation factor, 1 = plain Gauss-Seidel), which in the linear case is Duckett's
// information-weighted mean of the poses the neighbours predict. Cost of one pose update:
// O(degree · D³); a sweep O(E D² + N D³). Information travels one edge per sweep, which is
// why long loops converge slowly (the reason for the multi-level version).
#pragma once

#include "slamkit/solvers/relaxer.h"

namespace slamkit {

struct RelaxationOptions {
  RelaxerStop stop;
  double over_relaxation = 1.0;  ///< ω in (0, 2)
};

RelaxerSummary optimize_relaxation(PoseGraph& g, const RelaxationOptions& options = {});

}  // namespace slamkit
