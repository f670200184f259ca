#include "slamkit/solvers/marginal_information.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "slamkit/core/error.h"

namespace slamkit {

MarginalInformation marginal_information(const FactorGraph& graph, const Values& values, const std::vector<Key>& keys) {
  // Columns: first the requested keys (block c), then every other free variable (block x).
  std::vector<int> column(values.size(), -1);
  int nc = 0;
  std::unordered_map<Key, std::size_t> key_slot;
  for (std::size_t s = 0; s < keys.size(); ++s) {
    const std::size_t i = values.index_of(keys[s]);
    if (values.fixed(i)) throw InputError("", 0, "key", "marginal of fixed variable " + key_to_string(keys[s]));
    column[i] = nc;
    nc += values.manifold(i).tangent_dim();
    key_slot[keys[s]] = s;
  }
  int n = nc;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (column[i] >= 0 || values.fixed(i)) continue;
    column[i] = n;
    n += values.manifold(i).tangent_dim();
  }
  MarginalInformation out;
  out.factors_per_key.assign(keys.size(), 0);
  std::vector<Eigen::Triplet<double>> triplets;
  int row = 0;
  std::vector<double> residual, jac;
  for (const auto& fp : graph) {
    const Factor& f = *fp;
    const int m = f.residual_dim();
    std::vector<const double*> params;
    std::vector<std::vector<double>> J(f.keys().size());
    std::vector<double*> jptr;
    for (std::size_t k = 0; k < f.keys().size(); ++k) {
      const std::size_t i = values.index_of(f.keys()[k]);
      params.push_back(values.params(i));
      J[k].assign(static_cast<std::size_t>(m * values.manifold(i).tangent_dim()), 0.0);
      jptr.push_back(values.fixed(i) ? nullptr : J[k].data());
      const auto slot = key_slot.find(f.keys()[k]);
      if (slot != key_slot.end()) ++out.factors_per_key[slot->second];
    }
    residual.assign(static_cast<std::size_t>(m), 0.0);
    if (!std::isfinite(f.linearize(params.data(), residual.data(), jptr.data())))
      throw NumericalError("marginal_information: a factor does not evaluate to a finite number");
    for (std::size_t k = 0; k < f.keys().size(); ++k) {
      if (!jptr[k]) continue;
      const std::size_t i = values.index_of(f.keys()[k]);
      const int d = values.manifold(i).tangent_dim();
      for (int c = 0; c < d; ++c)
        for (int r = 0; r < m; ++r) {
          const double v = J[k][static_cast<std::size_t>(c * m + r)];  // column-major
          if (v != 0.0) triplets.emplace_back(row + r, column[i] + c, v);
        }
    }
    row += m;
  }
  Eigen::SparseMatrix<double> Jm(row, n);
  Jm.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SparseMatrix<double> H = (Jm.transpose() * Jm).pruned();
  const Eigen::MatrixXd Hcc = Eigen::MatrixXd(H.topLeftCorner(nc, nc));
  out.hessian_diag = Hcc.diagonal();
  out.schur = Hcc;
  const int nx = n - nc;
  if (nx == 0) return out;
  const Eigen::SparseMatrix<double> Hxx = H.bottomRightCorner(nx, nx);
  const Eigen::MatrixXd Hxc = Eigen::MatrixXd(H.bottomLeftCorner(nx, nc));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Hxx);
  if (ldlt.info() != Eigen::Success || (ldlt.vectorD().array() <= 0.0).any()) {
    out.eliminated_ok = false;
    return out;
  }
  const Eigen::MatrixXd X = ldlt.solve(Hxc);
  out.schur = Hcc - Hxc.transpose() * X;
  out.schur = 0.5 * (out.schur + out.schur.transpose());
  return out;
}

}  // namespace slamkit
