#include "slamkit/vio/marginalization.h"

#include <algorithm>
#include <set>

#include "slamkit/core/error.h"
#include "slamkit/linear/normal_equations.h"
#include "slamkit/linear/schur_complement.h"

namespace slamkit {
namespace {

// The dense symmetric matrix M as a BlockSparseMatrix with every block present.
BlockSparseMatrix dense_blocks(const Eigen::MatrixXd& M, const std::vector<int>& dims) {
  std::vector<std::pair<int, int>> pairs;
  const int n = static_cast<int>(dims.size());
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) pairs.emplace_back(i, j);
  BlockSparseMatrix A(dims, pairs);
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) A.block(i, j) = M.block(A.block_start(i), A.block_start(j), dims[i], dims[j]);
  return A;
}

}  // namespace

MarginalSystem marginalize(const FactorGraph& factors, const Values& values, const std::vector<Key>& first,
                           const std::vector<Key>& second, const ThreadPool& pool) {
  // Elimination order over Values indices: first, second, then the rest of the factors' variables.
  const std::set<Key> f(first.begin(), first.end()), s(second.begin(), second.end());
  std::vector<Key> rest;
  std::set<Key> seen(f);
  seen.insert(s.begin(), s.end());
  for (const auto& fac : factors)
    for (Key k : fac->keys())
      if (seen.insert(k).second) rest.push_back(k);
  if (rest.empty()) throw std::invalid_argument("marginalize: no variable would be left");
  EliminationOrder order;
  order.method = "marginalization";
  for (const std::vector<Key>* group : {&first, &second, static_cast<const std::vector<Key>*>(&rest)})
    for (Key k : *group) order.order.push_back(static_cast<int>(values.index_of(k)));
  NormalEquations ne(factors, values, OrderingMethod::kAuto, &order);
  const double cost = ne.linearize(values, pool);
  if (!std::isfinite(cost)) throw NumericalError("marginalize: a factor does not evaluate to a finite number");
  if (ne.num_free_variables() != static_cast<int>(first.size() + second.size() + rest.size()))
    throw std::invalid_argument("marginalize: every marginalized variable must be free and used by a factor");

  // NormalEquations postorders the given order: read back which key each block holds.
  const int nb = ne.num_free_variables();
  std::vector<Key> block_key(nb);
  for (int b = 0; b < nb; ++b) block_key[b] = values.key(ne.free_variable(b));
  SchurOptions so;
  so.method = SchurMethod::kDense;
  Eigen::MatrixXd S;
  Eigen::VectorXd r;
  std::vector<Key> s_keys;  // blocks of S, in order
  std::vector<int> s_dims;
  if (!first.empty()) {
    std::vector<char> elim(nb, 0);
    for (int b = 0; b < nb; ++b) elim[b] = f.count(block_key[b]) ? 1 : 0;
    SchurComplementSolver s1(elim, pool, so);
    s1.analyze(ne.hessian());
    if (!s1.reduced_system(ne.hessian(), ne.gradient().data(), &S, &r))
      throw NumericalError("marginalize: a marginalized variable has no positive-definite information");
    for (int b = 0; b < nb; ++b)
      if (!elim[b]) s_keys.push_back(block_key[b]), s_dims.push_back(ne.hessian().block_dim(b));
  } else {
    S = ne.hessian().to_dense();
    r = ne.gradient();
    for (int b = 0; b < nb; ++b) s_keys.push_back(block_key[b]), s_dims.push_back(ne.hessian().block_dim(b));
  }
  // Permute S to the order second, rest (pass 2 needs the eliminated blocks first).
  std::vector<int> starts(s_keys.size() + 1, 0);
  for (std::size_t a = 0; a < s_keys.size(); ++a) starts[a + 1] = starts[a] + s_dims[a];
  std::vector<int> perm;  // new block → old block
  for (const std::vector<Key>* group : {&second, static_cast<const std::vector<Key>*>(&rest)})
    for (Key k : *group) perm.push_back(static_cast<int>(std::find(s_keys.begin(), s_keys.end(), k) - s_keys.begin()));
  std::vector<int> dims, new_starts(perm.size() + 1, 0);
  for (std::size_t a = 0; a < perm.size(); ++a) dims.push_back(s_dims[perm[a]]), new_starts[a + 1] = new_starts[a] + dims[a];
  Eigen::MatrixXd P(S.rows(), S.cols());
  Eigen::VectorXd q(r.size());
  for (std::size_t a = 0; a < perm.size(); ++a) {
    q.segment(new_starts[a], dims[a]) = r.segment(starts[perm[a]], dims[a]);
    for (std::size_t c = 0; c < perm.size(); ++c)
      P.block(new_starts[a], new_starts[c], dims[a], dims[c]) = S.block(starts[perm[a]], starts[perm[c]], dims[a], dims[c]);
  }
  S = std::move(P), r = std::move(q);
  if (!second.empty()) {
    const BlockSparseMatrix A = dense_blocks(S, dims);
    std::vector<char> elim(dims.size(), 0);
    std::fill(elim.begin(), elim.begin() + second.size(), 1);
    SchurComplementSolver s2(elim, pool, so);
    s2.analyze(A);
    Eigen::MatrixXd S2;
    Eigen::VectorXd r2;
    if (!s2.reduced_system(A, r.data(), &S2, &r2))
      throw NumericalError("marginalize: a marginalized variable has no positive-definite information");
    S = std::move(S2), r = std::move(r2);
  }
  return {rest, S, r};
}

}  // namespace slamkit
