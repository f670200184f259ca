// Whole-graph check of analytic Jacobians against central differences in the tangent
// space: J_k(:, c) ≈ (r(x_k ⊞ h e_c) − r(x_k ⊞ −h e_c)) / 2h on the raw residuals.
// Entry-wise relative error |a − n| / max(1, |n|); the report names the worst entry.
#pragma once

#include <string>

#include "slamkit/core/factor_graph.h"

namespace slamkit {

struct JacobianCheckResult {
  bool ok = true;
  double worst_error = 0.0;
  std::size_t factor = 0, variable = 0;  ///< where the worst entry is
  int row = 0, col = 0;
  double analytic = 0.0, numeric = 0.0;
  std::size_t factors_checked = 0;
  std::string message() const;
};

JacobianCheckResult check_jacobians(const FactorGraph& graph, const Values& values, double tolerance = 1e-6,
                                    double step = 1e-6);

}  // namespace slamkit
