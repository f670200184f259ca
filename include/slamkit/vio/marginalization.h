// Marginalization of variables out of a set of factors, by the Schur complement of
// linear/schur_complement.h (the facility bundle adjustment uses), in two passes:
//   1. `first`  (e.g. the inverse depths anchored in the leaving keyframe: pairwise
//      non-adjacent, all of one size) out of the Gauss-Newton system H δ = −g of `factors`;
//   2. `second` (e.g. the leaving keyframe's state) out of the reduced system of pass 1.
// Result: H*, g* on the remaining variables of `factors` (in `kept` order) around the
// current values, from which factors/marginalization_prior.h builds the prior.
// Robust kernels are linearized as in the optimizer (Triggs' correction).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/parallel.h"

namespace slamkit {

struct MarginalSystem {
  std::vector<Key> kept;  ///< variables left, in the order of H and g
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
};

/// Throws InputError if a key is missing, std::invalid_argument if `first` are adjacent or
/// of different sizes, NumericalError if a marginalized block is not positive definite.
MarginalSystem marginalize(const FactorGraph& factors, const Values& values, const std::vector<Key>& first,
                           const std::vector<Key>& second, const ThreadPool& pool);

}  // namespace slamkit
