// Fill-reducing elimination orders on graphs (the block graph of a sparse system).
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstring>
#include <numeric>

#include "slamkit/core/error.h"
#include "slamkit/linear/sparse_cholesky.h"

#ifdef SLAMKIT_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace slamkit {
namespace {

// Upper-triangular CSC pattern (with diagonal) of an undirected graph.
void upper_pattern(int n, const std::vector<std::pair<int, int>>& edges, std::vector<int>* col_ptr,
                   std::vector<int>* rows) {
  std::vector<std::pair<int, int>> e;
  e.reserve(edges.size() + n);
  for (auto [a, b] : edges) {
    if (a < 0 || b < 0 || a >= n || b >= n) throw InputError("", 0, "", "elimination order: node out of range");
    if (a != b) e.emplace_back(std::min(a, b), std::max(a, b));
  }
  for (int i = 0; i < n; ++i) e.emplace_back(i, i);
  std::sort(e.begin(), e.end(), [](const auto& x, const auto& y) {
    return x.second != y.second ? x.second < y.second : x.first < y.first;
  });
  e.erase(std::unique(e.begin(), e.end()), e.end());
  col_ptr->assign(n + 1, 0);
  rows->clear();
  for (const auto& [i, j] : e) {
    ++(*col_ptr)[j + 1];
    rows->push_back(i);
  }
  for (int j = 0; j < n; ++j) (*col_ptr)[j + 1] += (*col_ptr)[j];
}

#ifdef SLAMKIT_HAVE_CHOLMOD
EliminationOrder cholmod_order(int n, std::vector<int>& col_ptr, std::vector<int>& rows, int method) {
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.error_handler = nullptr;
  c.supernodal = CHOLMOD_SIMPLICIAL;
  c.nmethods = 1;
  c.method[0].ordering = method;
  c.postorder = 1;
  cholmod_sparse G;
  std::memset(&G, 0, sizeof(G));
  G.nrow = G.ncol = static_cast<size_t>(n);
  G.nzmax = rows.size();
  G.p = col_ptr.data();
  G.i = rows.data();
  G.stype = 1;
  G.itype = CHOLMOD_INT;
  G.xtype = CHOLMOD_PATTERN;
  G.dtype = CHOLMOD_DOUBLE;
  G.sorted = 1;
  G.packed = 1;
  cholmod_factor* L = cholmod_analyze(&G, &c);
  if (!L) {
    cholmod_finish(&c);
    throw NumericalError("CHOLMOD ordering failed");
  }
  EliminationOrder out;
  out.order.assign(static_cast<int*>(L->Perm), static_cast<int*>(L->Perm) + n);
  out.flops = c.fl;
  out.method = method == CHOLMOD_AMD ? "AMD" : method == CHOLMOD_METIS ? "METIS" : "NESDIS";
  cholmod_free_factor(&L, &c);
  cholmod_finish(&c);
  return out;
}
#endif

EliminationOrder eigen_amd(int n, const std::vector<int>& col_ptr, const std::vector<int>& rows) {
  std::vector<double> ones(rows.size(), 1.0);
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>> U(n, n, static_cast<int>(rows.size()),
                                                                              col_ptr.data(), rows.data(), ones.data());
  const Eigen::SparseMatrix<double, Eigen::ColMajor, int> A = U.selfadjointView<Eigen::Upper>();
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P;
  Eigen::AMDOrdering<int>()(A, P);
  EliminationOrder out;
  out.order.resize(n);
  for (int i = 0; i < n; ++i) out.order[P.indices()[i]] = i;  // P maps old → new position
  out.method = "AMD (Eigen)";
  return out;
}

}  // namespace

EliminationOrder compute_elimination_order(int n, const std::vector<std::pair<int, int>>& edges,
                                           OrderingMethod method) {
  EliminationOrder out;
  if (method == OrderingMethod::kNatural || n == 0) {
    out.order.resize(n);
    std::iota(out.order.begin(), out.order.end(), 0);
    out.method = "natural";
    return out;
  }
  std::vector<int> col_ptr, rows;
  upper_pattern(n, edges, &col_ptr, &rows);
#ifdef SLAMKIT_HAVE_CHOLMOD
  switch (method) {
    case OrderingMethod::kAmd: return cholmod_order(n, col_ptr, rows, CHOLMOD_AMD);
    case OrderingMethod::kMetis: return cholmod_order(n, col_ptr, rows, CHOLMOD_METIS);
    case OrderingMethod::kNesdis: return cholmod_order(n, col_ptr, rows, CHOLMOD_NESDIS);
    default: break;
  }
  // Auto: nested dissection pays for its slower ordering only on large factorizations.
  EliminationOrder best = cholmod_order(n, col_ptr, rows, CHOLMOD_AMD);
  if (best.flops >= 2e6) {
    for (int m : {CHOLMOD_METIS, CHOLMOD_NESDIS}) {
      EliminationOrder candidate = cholmod_order(n, col_ptr, rows, m);
      if (candidate.flops < best.flops) best = std::move(candidate);
    }
  }
  return best;
#else
  return eigen_amd(n, col_ptr, rows);
#endif
}

}  // namespace slamkit
