#include "slamkit/factors/hogman.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <ctime>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/solvers/relaxer_pose_traits.h"

namespace slamkit {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

template <int D>
class Hierarchy {
 public:
  using T = detail::RelaxerPose<D>;
  using Pose = typename T::Pose;
  using Vec = typename T::Vec;
  using Mat = typename T::Mat;

  Hierarchy(const HogmanOptions& o, int levels) : o_(o) {
    levels_.resize(levels + 1);
    for (auto& L : levels_) L.graph = std::make_unique<PoseGraph>();
  }
  int num_levels() const { return static_cast<int>(levels_.size()); }
  PoseGraph& fine() { return *levels_[0].graph; }

  // Adds a node to level l (and, for a new group, its representative to level l + 1).
  void add_node(int l, const GraphVertex& v) {
    Level& L = levels_[l];
    L.graph->add_vertex(v);
    const int idx = static_cast<int>(L.graph->vertices().size()) - 1;
    L.incident.emplace_back();
    if (l + 1 >= num_levels()) return;
    if (L.members.empty() || static_cast<int>(L.members.back().size()) >= o_.group_size) {
      L.members.push_back({idx});
      L.intra.emplace_back();
      L.group.push_back(static_cast<int>(L.members.size()) - 1);
      add_node(l + 1, v);  // the representative: same id, same pose
    } else {
      L.members.back().push_back(idx);
      L.group.push_back(static_cast<int>(L.members.size()) - 1);
      L.dirty_groups.insert(L.group.back());
      L.stale.insert(L.group.back());
    }
  }

  // Adds an edge to level l; returns true if it joins groups that are not neighbours in the
  // sequence (a loop closure for the coarse levels).
  bool add_edge(int l, const GraphEdge& e) {
    Level& L = levels_[l];
    const int a = static_cast<int>(*L.graph->index_of(e.from)), b = static_cast<int>(*L.graph->index_of(e.to));
    const int k = static_cast<int>(L.graph->edges.size());
    L.graph->edges.push_back(e);
    L.ends.emplace_back(a, b);
    L.incident[a].push_back(k);
    L.incident[b].push_back(k);
    if (l + 1 >= num_levels()) return false;
    const int ga = L.group[a], gb = L.group[b];
    L.stale.insert(ga);
    L.stale.insert(gb);
    if (ga == gb) {
      L.intra[ga].push_back(k);
      L.dirty_groups.insert(ga);
      return false;
    }
    const auto key = std::minmax(ga, gb);
    L.inter[key].push_back(k);
    L.dirty_pairs.insert(key);
    return std::abs(ga - gb) > 1;
  }

  // Re-condenses what changed, level by level. Returns true if a coarse edge was added
  // between non-neighbouring groups of some level.
  bool update_condensation() {
    bool loop = false;
    for (int l = 0; l + 1 < num_levels(); ++l) {
      Level& L = levels_[l];
      for (int g : L.dirty_groups)
        for (const auto& [key, edges] : L.inter)
          if (key.first == g || key.second == g) L.dirty_pairs.insert(key);
      L.dirty_groups.clear();
      for (const auto& key : L.dirty_pairs) loop |= condense(l, key.first, key.second);
      L.dirty_pairs.clear();
    }
    return loop;
  }

  // Gauss-Newton on the coarsest level from its current estimates (after `init`).
  void solve_top(InitMethod init) { solve_level(num_levels() - 1, init); }

  // Gauss-Newton on level l from its current estimates (after `init`).
  void solve_level(int l, InitMethod init) {
    PoseGraph& top = *levels_[l].graph;
    if (top.edges.empty()) return;
    PoseGraphOptimizerOptions po;
    po.init = init;
    po.optimizer.algorithm = Algorithm::kGaussNewton;
    po.optimizer.max_iterations = l + 1 == num_levels() ? o_.top_iterations : o_.level_iterations;
    po.optimizer.num_threads = o_.threads;
    optimize_pose_graph(top, po);
  }

  // Moves every group rigidly with its representative, from the top down, and refines the
  // groups whose representative moved.
  // refine_stale: also refine the groups that received nodes or edges since their last
  // refinement (online: the new data); batch refines only where the coarse solution moved.
  void propagate_down(bool solve_levels, bool refine_stale) {
    for (int l = num_levels() - 2; l >= 0; --l) {
      Level& L = levels_[l];
      const PoseGraph& C = *levels_[l + 1].graph;
      std::vector<int> moved;
      for (std::size_t gi = 0; gi < L.members.size(); ++gi) {  // all rigid moves first ...
        const std::vector<int>& m = L.members[gi];
        const Pose rep = T::pose(L.graph->vertices()[m[0]]);
        const Pose& target = T::pose(C.vertices()[gi]);
        const Vec change = rep.between(target).log();
        if (!(change.cwiseAbs().maxCoeff() > o_.refine_threshold)) {
          if (refine_stale && L.stale.count(static_cast<int>(gi))) moved.push_back(static_cast<int>(gi));
          continue;
        }
        const Pose delta = target * rep.inverse();
        for (int k : m) {
          Pose& x = T::pose(L.graph->vertex_at(k));
          x = delta * x;
        }
        T::pose(L.graph->vertex_at(m[0])) = target;
        moved.push_back(static_cast<int>(gi));
      }
      for (int sweep = 0; sweep < o_.refine_sweeps; ++sweep)  // ... then block Gauss-Seidel over the moved groups
        for (int gi : moved)
          if (L.members[gi].size() > 1) refine_group(l, gi);
      L.stale.clear();
      if (solve_levels && l > 0) solve_level(l, InitMethod::kNone);  // the intermediate levels as a whole
    }
  }

 private:
  struct Level {
    std::unique_ptr<PoseGraph> graph;
    std::vector<std::pair<int, int>> ends;
    std::vector<std::vector<int>> incident;
    std::vector<int> group;                  // node → group (= node of level l + 1)
    std::vector<std::vector<int>> members;   // group → nodes, the representative first
    std::vector<std::vector<int>> intra;     // group → edges inside it
    std::map<std::pair<int, int>, std::vector<int>> inter;  // group pair → edges between them
    std::map<std::pair<int, int>, int> condensed;           // group pair → edge of level l + 1
    std::set<int> dirty_groups;
    std::set<int> stale;  // groups that received a node or an edge since their last refinement
    std::set<std::pair<int, int>> dirty_pairs;
  };

  // Dense Gauss-Newton over `nodes` of level l (those flagged fixed, and every node outside the
  // list, held constant) with the given edges. If marginal_of ≥ 0, *marginal receives the
  // information of that node's marginal at the solution. False if the system is singular.
  bool local_solve(int l, const std::vector<int>& nodes, const std::vector<char>& fixed, const std::vector<int>& edges,
                   int marginal_of, Mat* marginal) {
    Level& L = levels_[l];
    std::unordered_map<int, int> var;
    int m = 0, marginal_var = -1;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      if (!fixed[i]) {
        if (static_cast<int>(i) == marginal_of) marginal_var = m;
        var[nodes[i]] = m++;
      }
    if (m == 0) return true;
    auto index = [&](int node) {
      const auto it = var.find(node);
      return it == var.end() ? -1 : it->second;
    };
    Eigen::MatrixXd H(m * D, m * D);
    Eigen::VectorXd b(m * D);
    auto assemble = [&] {
      H.setZero();
      b.setZero();
      for (int k : edges) {
        const GraphEdge& e = L.graph->edges[k];
        const auto [na, nb] = L.ends[k];
        Mat Ja, Jb;
        const Vec err = T::error(T::measurement(e), T::pose(L.graph->vertices()[na]), T::pose(L.graph->vertices()[nb]),
                                 &Ja, &Jb);
        const Mat& O = e.information;
        const int ia = index(na), ib = index(nb);
        if (ia >= 0) {
          H.template block<D, D>(ia * D, ia * D) += Ja.transpose() * O * Ja;
          b.template segment<D>(ia * D) += Ja.transpose() * O * err;
        }
        if (ib >= 0) {
          H.template block<D, D>(ib * D, ib * D) += Jb.transpose() * O * Jb;
          b.template segment<D>(ib * D) += Jb.transpose() * O * err;
        }
        if (ia >= 0 && ib >= 0) {
          const Mat off = Ja.transpose() * O * Jb;
          H.template block<D, D>(ia * D, ib * D) += off;
          H.template block<D, D>(ib * D, ia * D) += off.transpose();
        }
      }
    };
    auto factor_ok = [&](const Eigen::LDLT<Eigen::MatrixXd>& f) {
      return f.info() == Eigen::Success && f.vectorD().minCoeff() > 1e-12 * std::max(1.0, f.vectorD().maxCoeff());
    };
    for (int it = 0; it < o_.local_iterations; ++it) {
      assemble();
      const Eigen::LDLT<Eigen::MatrixXd> f(H);
      if (!factor_ok(f)) return false;
      const Eigen::VectorXd delta = -f.solve(b);
      if (!delta.allFinite()) return false;
      for (const auto& [node, v] : var) {
        Pose& x = T::pose(L.graph->vertex_at(node));
        x = x.plus(delta.template segment<D>(v * D));
      }
      if (delta.cwiseAbs().maxCoeff() < 1e-10) break;
    }
    if (marginal_var >= 0) {
      assemble();
      const Eigen::LDLT<Eigen::MatrixXd> f(H);
      if (!factor_ok(f)) return false;
      Eigen::MatrixXd E = Eigen::MatrixXd::Zero(m * D, D);
      E.template block<D, D>(marginal_var * D, 0).setIdentity();
      const Mat cov = f.solve(E).template block<D, D>(marginal_var * D, 0);
      *marginal = cov.ldlt().solve(Mat::Identity());
      if (!marginal->allFinite()) return false;
    }
    return true;
  }

  // The condensed edge between the representatives of groups g1 < g2 of level l.
  bool condense(int l, int g1, int g2) {
    Level& L = levels_[l];
    const std::vector<int>& m1 = L.members[g1];
    const std::vector<int>& m2 = L.members[g2];
    std::vector<int> nodes(m1);
    nodes.insert(nodes.end(), m2.begin(), m2.end());
    std::vector<char> fixed(nodes.size(), 0);
    fixed[0] = 1;
    std::vector<int> edges(L.intra[g1]);
    edges.insert(edges.end(), L.intra[g2].begin(), L.intra[g2].end());
    const std::vector<int>& between = L.inter.at({g1, g2});
    edges.insert(edges.end(), between.begin(), between.end());
    std::vector<Pose> saved;
    for (int k : nodes) saved.push_back(T::pose(L.graph->vertices()[k]));
    Mat info;
    const bool ok = local_solve(l, nodes, fixed, edges, static_cast<int>(m1.size()), &info);
    const Pose& x1 = T::pose(L.graph->vertices()[m1[0]]);
    const Pose& x2 = T::pose(L.graph->vertices()[m2[0]]);
    GraphEdge ce;
    ce.from = L.graph->vertices()[m1[0]].id;
    ce.to = L.graph->vertices()[m2[0]].id;
    ce.kind = D == 3 ? EdgeKind::kPose2Pose2 : EdgeKind::kPose3Pose3;
    const Pose z = ok ? x1.between(x2) : saved[0].between(saved[m1.size()]);
    T::measurement_ref(ce) = z;
    if (ok) {
      Mat Ja, Jb;
      T::error(z, x1, x2, &Ja, &Jb);  // e = 0 here; Jb maps the marginal into the edge's error
      const Mat Jinv = Jb.inverse();
      const Mat O = Jinv.transpose() * info * Jinv;
      ce.information = 0.5 * (O + O.transpose());
    } else {  // the two groups are not rigid on their own: keep the strongest direct edge's weight
      int best = between.front();
      for (int k : between)
        if (L.graph->edges[k].information.trace() > L.graph->edges[best].information.trace()) best = k;
      ce.information = L.graph->edges[best].information;
    }
    for (std::size_t i = 0; i < nodes.size(); ++i) T::pose(L.graph->vertex_at(nodes[i])) = saved[i];
    const auto it = L.condensed.find({g1, g2});
    if (it == L.condensed.end()) {
      L.condensed[{g1, g2}] = static_cast<int>(levels_[l + 1].graph->edges.size());
      return add_edge(l + 1, ce);
    }
    Level& C = levels_[l + 1];
    C.graph->edges[it->second] = ce;
    if (l + 2 < num_levels()) {  // the next level condenses this edge again
      const int ca = C.group[C.ends[it->second].first], cb = C.group[C.ends[it->second].second];
      if (ca == cb) C.dirty_groups.insert(ca);
      else C.dirty_pairs.insert(std::minmax(ca, cb));
    }
    return false;
  }

  // Re-optimizes a group's nodes with its representative and all neighbours held fixed.
  void refine_group(int l, int gi) {
    Level& L = levels_[l];
    const std::vector<int>& m = L.members[gi];
    std::vector<char> fixed(m.size(), 0);
    fixed[0] = 1;
    std::vector<int> edges;
    for (int k : m) edges.insert(edges.end(), L.incident[k].begin(), L.incident[k].end());
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<Pose> saved;
    for (int k : m) saved.push_back(T::pose(L.graph->vertices()[k]));
    if (!local_solve(l, m, fixed, edges, -1, nullptr))
      for (std::size_t i = 0; i < m.size(); ++i) T::pose(L.graph->vertex_at(m[i])) = saved[i];
  }

  HogmanOptions o_;
  std::vector<Level> levels_;
};

int levels_for(std::size_t n, const HogmanOptions& o) {
  int levels = 0;
  while (levels < o.max_levels && n > static_cast<std::size_t>(o.top_nodes)) {
    n = (n + o.group_size - 1) / o.group_size;
    ++levels;
  }
  return levels;
}

void check_options(const HogmanOptions& o) {
  if (o.group_size < 2 || o.max_levels < 0 || o.top_nodes < 1 || o.local_iterations < 1 || o.top_iterations < 1 ||
      o.refine_sweeps < 1)
    throw InputError("", 0, "hogman",
                     "group_size ≥ 2, max_levels ≥ 0, top_nodes, local_iterations, top_iterations, refine_sweeps ≥ 1");
}

// Vertices in id order, and per vertex the edges whose later end it is.
std::vector<std::size_t> id_order(const PoseGraph& g) {
  std::vector<std::size_t> order(g.vertices().size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return g.vertices()[a].id < g.vertices()[b].id; });
  return order;
}

template <int D>
void copy_poses(const PoseGraph& from, PoseGraph& to) {
  using T = detail::RelaxerPose<D>;
  for (std::size_t i = 0; i < to.vertices().size(); ++i)
    T::pose(to.vertex_at(i)) = T::pose(from.vertex(to.vertices()[i].id));
}

template <int D>
double hierarchy_pass(PoseGraph& g, const HogmanOptions& o) {
  Hierarchy<D> h(o, levels_for(g.vertices().size(), o));
  for (std::size_t i : id_order(g)) h.add_node(0, g.vertices()[i]);
  for (const GraphEdge& e : g.edges) h.add_edge(0, e);
  h.update_condensation();
  h.solve_top(o.top_init);
  h.propagate_down(o.batch_level_iterations, false);
  copy_poses<D>(h.fine(), g);
  return 1.0;
}

template <int D>
HogmanOnlineResult online(PoseGraph& g, const HogmanOptions& o) {
  using T = detail::RelaxerPose<D>;
  HogmanOnlineResult r;
  const auto t_start = std::chrono::steady_clock::now();
  Hierarchy<D> h(o, levels_for(g.vertices().size(), o));
  r.levels = h.num_levels() - 1;
  const std::vector<std::size_t> order = id_order(g);
  std::vector<std::size_t> rank(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = k;
  std::vector<std::vector<int>> arriving(order.size());  // edges whose later end is vertex k (rank)
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const std::size_t a = rank[*g.index_of(g.edges[e].from)], b = rank[*g.index_of(g.edges[e].to)];
    arriving[std::max(a, b)].push_back(static_cast<int>(e));
  }
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_seconds();
    GraphVertex v = g.vertices()[order[k]];
    // Initial guess from the earliest edge to a pose already there (the odometry, usually).
    for (int e : arriving[k]) {
      const GraphEdge& edge = g.edges[e];
      const bool forward = edge.to == v.id;
      const std::int64_t other = forward ? edge.from : edge.to;
      if (other == v.id) continue;
      const auto& x = T::pose(h.fine().vertex(other));
      T::pose(v) = forward ? x * T::measurement(edge) : x * T::measurement(edge).inverse();
      break;
    }
    h.add_node(0, v);
    bool loop = false;
    for (int e : arriving[k]) loop |= h.add_edge(0, g.edges[e]);
    loop |= h.update_condensation();
    if (loop) h.solve_top(InitMethod::kNone);
    // Moved groups, and those that received this pose or its edges; after a loop closure the
    // intermediate levels get a few Gauss-Newton iterations as a whole.
    h.propagate_down(loop && o.online_level_iterations, true);
    r.time_per_pose_s.push_back(seconds_since(t0));
    r.cpu_time_per_pose_s.push_back(cpu_seconds() - c0);
    r.graph_size.push_back(static_cast<int>(k + 1));
    r.top_solved.push_back(loop);
  }
  r.total_time_s = seconds_since(t_start);
  r.chi2_before_final_pass = total_chi2(h.fine());
  if (o.final_fine_pass) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpu_seconds();
    h.solve_top(InitMethod::kNone);
    h.propagate_down(true, true);
    PoseGraphOptimizerOptions po;
    po.init = InitMethod::kNone;
    po.optimizer.algorithm = Algorithm::kGaussNewton;
    po.optimizer.max_iterations = o.final_fine_iterations;
    po.optimizer.num_threads = o.threads;
    optimize_pose_graph(h.fine(), po);
    r.final_pass_time_s = seconds_since(t0);
    r.final_pass_cpu_time_s = cpu_seconds() - c0;
  }
  copy_poses<D>(h.fine(), g);
  r.final_chi2 = total_chi2(g);
  return r;
}

}  // namespace

RelaxerSummary optimize_hogman(PoseGraph& g, const HogmanOptions& options) {
  check_options(options);
  const RelaxerGraph rg = make_relaxer_graph(g);
  std::string fine_start = "the graph's estimates";
  auto step = [&](int iteration) -> double {
    if (iteration == 1) {
      if (options.fine_init != InitMethod::kNone)
        fine_start = to_string(initialize_pose_graph(g, options.fine_init, gauge_vertices(g)).used);
      return rg.dimension == 2 ? hierarchy_pass<3>(g, options) : hierarchy_pass<6>(g, options);
    }
    PoseGraphOptimizerOptions po;
    po.init = InitMethod::kNone;
    po.optimizer.algorithm = options.fine_algorithm;
    po.optimizer.function_tolerance = options.fine_function_tolerance;
    po.optimizer.num_threads = options.threads;
    optimize_pose_graph(g, po);
    return -1.0;  // the fine level is converged: done
  };
  RelaxerSummary s = run_relaxer(g, "hogman", options.stop, step, [] {});
  s.num_loop_closures = rg.num_loop_closures;
  s.notes.push_back("levels above the pose graph: " + std::to_string(levels_for(g.vertices().size(), options)) +
                    ", group size " + std::to_string(options.group_size) + "; fine level started from " + fine_start);
  return s;
}

HogmanOnlineResult hogman_online(PoseGraph& g, const HogmanOptions& options) {
  check_options(options);
  const RelaxerGraph rg = make_relaxer_graph(g);
  return rg.dimension == 2 ? online<3>(g, options) : online<6>(g, options);
}

}  // namespace slamkit
