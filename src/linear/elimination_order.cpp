// Fill-reducing elimination orders on graphs (the block graph of a sparse system).
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstring>
#include <numeric>

#include "slamkit/core/error.h"
#include "slamkit/linear/sparse_cholesky.h"

#ifdef SLAMKIT_HAVE_CHOLMOD
#include <amd.h>
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
  // Sorted by (column, row): two stable counting sorts, by row and then by column.
  std::vector<std::pair<int, int>> by_row(e.size());
  std::vector<int> start(static_cast<std::size_t>(n) + 1);
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<std::pair<int, int>>& from = pass == 0 ? e : by_row;
    std::vector<std::pair<int, int>>& to = pass == 0 ? by_row : e;
    std::fill(start.begin(), start.end(), 0);
    for (const auto& p : from) ++start[(pass == 0 ? p.first : p.second) + 1];
    for (int k = 0; k < n; ++k) start[k + 1] += start[k];
    for (const auto& p : from) to[start[pass == 0 ? p.first : p.second]++] = p;
  }
  col_ptr->assign(n + 1, 0);
  rows->clear();
  rows->reserve(e.size());
  for (std::size_t q = 0; q < e.size(); ++q) {
    if (q > 0 && e[q] == e[q - 1]) continue;  // duplicate edge
    ++(*col_ptr)[e[q].second + 1];
    rows->push_back(e[q].first);
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

// AMD alone (amd_order, with CHOLMOD's settings: dense rows above 10 sqrt(n), aggressive
// absorption), without cholmod_analyze's elimination tree, postorder and column counts: the
// postorder below redoes those, and the flop count comes from its column counts.
EliminationOrder amd_direct(int n, const std::vector<int>& col_ptr, const std::vector<int>& rows) {
  double control[AMD_CONTROL], info[AMD_INFO];
  amd_defaults(control);
  control[AMD_DENSE] = 10.0;
  control[AMD_AGGRESSIVE] = 1.0;
  EliminationOrder out;
  out.order.resize(n);
  const int status = amd_order(n, col_ptr.data(), rows.data(), out.order.data(), control, info);
  if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED) throw NumericalError("AMD ordering failed");
  out.method = "AMD";
  return out;
}

// AMD after the series reductions: nodes of degree ≤ 2 are eliminated first, in the order
// they appear (degree 1: no fill; degree 2 with neighbours a, b: the edge a–b, which replaces
// the two edges through the node, so no list ever grows), then AMD orders what is left.
// Minimum degree starts the same way; doing it here is O(n) where AMD spends about a thousand
// instructions per node, and pose graphs are mostly chains of odometry between loop closures.
// A node next to one with more than kHubDegree neighbours is left to AMD (bounded work per
// elimination: a hub with many chains would otherwise be scanned once per chain). Used where
// the reduction removes at least half of the nodes (odometry chains between loop closures:
// 88-97 % on INTEL, MITb, CSAIL), where the fill stays within ±2 % of AMD's own order.
EliminationOrder amd_after_series_reduction(int n, const std::vector<int>& col_ptr, const std::vector<int>& rows) {
  constexpr int kHubDegree = 32;
  // Symmetric adjacency lists (CSR, no diagonal); deg[k] counts the live entries of k's list,
  // len(k) = start[k + 1] − start[k] bounds them (dead entries are skipped, never compacted).
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0), deg(n, 0);
  for (int j = 0; j < n; ++j)
    for (int q = col_ptr[j]; q < col_ptr[j + 1]; ++q)
      if (rows[q] != j) ++deg[rows[q]], ++deg[j];
  // Chains only shorten by elimination: with fewer than half of the nodes at degree ≤ 2 at
  // the start, the reduction rarely reaches half (below) and is not worth building.
  if (2 * std::count_if(deg.begin(), deg.end(), [](int d) { return d <= 2; }) < n) return amd_direct(n, col_ptr, rows);
  for (int k = 0; k < n; ++k) start[k + 1] = start[k] + deg[k];
  std::vector<int> adj(start[n]);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int j = 0; j < n; ++j)
      for (int q = col_ptr[j]; q < col_ptr[j + 1]; ++q)
        if (rows[q] != j) adj[fill[rows[q]]++] = j, adj[fill[j]++] = rows[q];
  }
  std::vector<char> gone(n, 0);
  const auto len = [&](int k) { return start[k + 1] - start[k]; };
  const auto find = [&](int a, int x) -> int* {  // x's entry in a's list (x live), or null
    for (int q = start[a]; q < start[a + 1]; ++q)
      if (adj[q] == x) return &adj[q];
    return nullptr;
  };
  std::vector<int> eliminated, queue;
  eliminated.reserve(n);
  for (int k = 0; k < n; ++k)
    if (deg[k] <= 2) queue.push_back(k);
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const int v = queue[h];
    if (gone[v] || deg[v] > 2) continue;
    int nb[2], m = 0;
    for (int q = start[v]; q < start[v + 1] && m < deg[v]; ++q)
      if (!gone[adj[q]]) nb[m++] = adj[q];
    bool hub = false;
    for (int t = 0; t < m; ++t) hub = hub || len(nb[t]) > kHubDegree;
    if (hub) continue;
    gone[v] = 1;
    eliminated.push_back(v);
    if (m == 2 && !find(nb[0], nb[1])) {  // the chain closes over v: a–b replaces a–v–b
      *find(nb[0], v) = nb[1];
      *find(nb[1], v) = nb[0];
      continue;
    }
    for (int t = 0; t < m; ++t)  // v's entries die; its neighbours may join the queue
      if (--deg[nb[t]] <= 2) queue.push_back(nb[t]);
  }
  const int kept = n - static_cast<int>(eliminated.size());
  // Where chains are a minority the reduction saves AMD little and changes its tie-breaks on
  // what is left (measured: up to 13 % more factorization flops on cubicle, 10 % on M3500, where
  // it removes 2 % and 32 % of the nodes): AMD orders the whole graph.
  if (2 * kept > n) return amd_direct(n, col_ptr, rows);
  EliminationOrder out;
  out.method = "AMD";
  out.order = std::move(eliminated);
  if (kept == 0) return out;
  // The remaining graph, relabelled, both triangles, columns sorted (AMD's preferred input).
  std::vector<int> label(n, -1), node;
  node.reserve(kept);
  for (int k = 0; k < n; ++k)
    if (!gone[k]) label[k] = static_cast<int>(node.size()), node.push_back(k);
  std::vector<int> rp(static_cast<std::size_t>(kept) + 1, 0), ri;
  ri.reserve(adj.size());
  for (int j = 0; j < kept; ++j) {
    const int k = node[j];
    const std::size_t first = ri.size();
    for (int q = start[k]; q < start[k + 1]; ++q)
      if (!gone[adj[q]]) ri.push_back(label[adj[q]]);
    std::sort(ri.begin() + static_cast<std::ptrdiff_t>(first), ri.end());
    rp[j + 1] = static_cast<int>(ri.size());
  }
  const EliminationOrder rest = amd_direct(kept, rp, ri);
  for (int p : rest.order) out.order.push_back(node[p]);
  return out;
}
#endif

// The ordering without CHOLMOD (kept compiled either way).
[[maybe_unused]] EliminationOrder eigen_amd(int n, const std::vector<int>& col_ptr, const std::vector<int>& rows) {
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

// Postorders the elimination tree of the graph under `order`: every subtree becomes a
// contiguous range, so supernodes stay together and a matrix stored in this order can be
// factorized as is (no symbolic or numeric permutation). Fill is unchanged.
// With `flops`: also the Cholesky flops of the pattern under this order, Σ_j c_j² over the
// column counts c_j of L (diagonal included; CHOLMOD's definition), from the row subtrees of
// the elimination tree: O(nnz(L)).
std::vector<int> postorder(int n, const std::vector<std::pair<int, int>>& edges, const std::vector<int>& order,
                           double* flops = nullptr) {
  std::vector<int> label(n);  // node → position in `order`
  for (int k = 0; k < n; ++k) label[order[k]] = k;
  // By position: the neighbours at earlier positions, in edge order (flat arrays, counting sort).
  std::vector<int> lower_start(static_cast<std::size_t>(n) + 1, 0), lower;
  for (auto [a, b] : edges)
    if (a != b) ++lower_start[std::max(label[a], label[b]) + 1];
  for (int k = 0; k < n; ++k) lower_start[k + 1] += lower_start[k];
  lower.resize(lower_start[n]);
  {
    std::vector<int> fill(lower_start.begin(), lower_start.end() - 1);
    for (auto [a, b] : edges) {
      const int la = label[a], lb = label[b];
      if (la < lb) lower[fill[lb]++] = la;
      if (lb < la) lower[fill[la]++] = lb;
    }
  }
  // Elimination tree (Liu's algorithm with path compression).
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k) {
    for (int q = lower_start[k]; q < lower_start[k + 1]; ++q) {
      const int i = lower[q];
      int r = i;
      while (ancestor[r] != -1 && ancestor[r] != k) {
        const int next = ancestor[r];
        ancestor[r] = k;
        r = next;
      }
      if (ancestor[r] == -1) ancestor[r] = k, parent[r] = k;
    }
  }
  if (flops) {
    // Row k of L = the union of the etree paths from k's earlier neighbours up to k.
    std::vector<int> count(n, 1), mark(n, -1);
    for (int k = 0; k < n; ++k) {
      mark[k] = k;
      for (int q = lower_start[k]; q < lower_start[k + 1]; ++q)
        for (int x = lower[q]; mark[x] != k; x = parent[x]) mark[x] = k, ++count[x];
    }
    double fl = 0.0;
    for (int c : count) fl += static_cast<double>(c) * c;
    *flops = fl;
  }
  // Depth-first postorder, children (and roots) in increasing position.
  std::vector<int> head(n, -1), next(n, -1);
  for (int k = n - 1; k >= 0; --k)
    if (parent[k] >= 0) next[k] = head[parent[k]], head[parent[k]] = k;
  std::vector<int> result, stack;
  result.reserve(n);
  for (int root = 0; root < n; ++root) {
    if (parent[root] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int top = stack.back();
      const int child = head[top];
      if (child < 0) {
        stack.pop_back();
        result.push_back(order[top]);
      } else {
        head[top] = next[child];
        stack.push_back(child);
      }
    }
  }
  return result;
}

}  // namespace

constexpr double kNestedDissectionBlockFlops = 1e8;
// Nested dissection (METIS and NESDIS, both tried) costs ~2 us per block edge each (1M-pose
// Manhattan: 4.4 and 4.9 s for 2.37M edges, against 0.8 s for AMD) and has saved at most 30-45 %
// of AMD's flops (Manhattan 1M 30 %, a 100k-pose sphere 44 %). A block flop of a 3×3-block
// factorization takes ~2.9 ns here (more for larger blocks), so over ~8 factorizations (init,
// symbolic analysis, iterations) the saving, ≤ 0.3 · 8 · 2.9 ns · flops, exceeds the ~4 us per
// edge that the two orderings cost only above ~575 block flops per edge of the AMD order: the
// 100k sphere has 4 800 (METIS saves 7 s for 0.7 s), the 1M Manhattan 167 (NESDIS cost 9 s
// to save 1.3 s).
constexpr double kNestedDissectionFlopsPerEdge = 600;

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
  EliminationOrder best;
#ifdef SLAMKIT_HAVE_CHOLMOD
  switch (method) {
    case OrderingMethod::kAmd:
      best = amd_after_series_reduction(n, col_ptr, rows);
      best.order = postorder(n, edges, best.order, &best.flops);
      return best;
    case OrderingMethod::kMetis: best = cholmod_order(n, col_ptr, rows, CHOLMOD_METIS); break;
    case OrderingMethod::kNesdis: best = cholmod_order(n, col_ptr, rows, CHOLMOD_NESDIS); break;
    default:
      // Auto: nested dissection pays for its slower ordering only on large factorizations.
      // Measured on the pose-graph datasets (up to 1.2e9 scalar flops per factorization),
      // METIS/NESDIS save ≤ 20% of the flops but no time: supernodes of the AMD order are
      // as efficient, and the orderings themselves cost 10–120 ms. So AMD alone below
      // kNestedDissectionBlockFlops (≈ 2e10 scalar flops for 6×6 blocks, ~1 s factorizations), and
      // below kNestedDissectionFlopsPerEdge, where the orderings cost more than they save.
      best = amd_after_series_reduction(n, col_ptr, rows);
      best.order = postorder(n, edges, best.order, &best.flops);
      if (best.flops < kNestedDissectionBlockFlops ||
          best.flops < kNestedDissectionFlopsPerEdge * static_cast<double>(rows.size() - static_cast<std::size_t>(n)))
        return best;  // postordered already
      for (int m : {CHOLMOD_METIS, CHOLMOD_NESDIS}) {
        EliminationOrder candidate = cholmod_order(n, col_ptr, rows, m);
        if (candidate.flops < best.flops) best = std::move(candidate);
      }
      // (postordering the postordered AMD order again, should it stay the best, is the identity)
  }
#else
  best = eigen_amd(n, col_ptr, rows);
#endif
  best.order = postorder(n, edges, best.order);
  return best;
}

EliminationOrder postordered(int n, const std::vector<std::pair<int, int>>& edges, EliminationOrder order) {
  if (static_cast<int>(order.order.size()) != n) throw InputError("", 0, "order", "elimination order has the wrong size");
  order.order = postorder(n, edges, order.order);
  return order;
}

}  // namespace slamkit
