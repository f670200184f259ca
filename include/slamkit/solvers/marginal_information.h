// Marginal information of a few variables at a point: the Schur complement of the Gauss-Newton
// Hessian H = JᵀJ (whitened, robustified Jacobians of all factors) onto those variables,
//     S = H_cc − H_cx H_xx⁻¹ H_xc,
// whose inverse is their marginal covariance (Laplace approximation). The other free variables
// are eliminated with a sparse LDLᵀ of H_xx; fixed variables take no part. For the few, dense,
// calibration-like variables of a large sparse problem.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/core/factor_graph.h"

namespace slamkit {

struct MarginalInformation {
  Eigen::MatrixXd schur;          ///< S, over the tangent coordinates of `keys` in order
  Eigen::VectorXd hessian_diag;   ///< diag(H_cc) before elimination (0: no factor sees the coordinate)
  std::vector<int> factors_per_key;  ///< how many factors involve each key
  bool eliminated_ok = true;      ///< false if H_xx was singular (then schur = H_cc)
};

/// Throws InputError if a key is absent or fixed.
MarginalInformation marginal_information(const FactorGraph& graph, const Values& values, const std::vector<Key>& keys);

}  // namespace slamkit
