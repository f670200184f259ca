#include "slamkit/solvers/pose_graph_init.h"

#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include "slamkit/core/error.h"
#include "slamkit/solvers/relaxer_init.h"

namespace slamkit {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

bool is_pose(const GraphVertex& v) { return v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPose3; }
bool is_pose_edge(const GraphEdge& e) { return e.kind == EdgeKind::kPose2Pose2 || e.kind == EdgeKind::kPose3Pose3; }

// Pose vertices renumbered 0..n−1, with the gauge ones marked; edge endpoints resolved.
struct PoseIndex {
  std::vector<std::size_t> vertex;      // pose k → graph vertex index
  std::vector<int> pose_of;             // graph vertex index → pose k or −1
  std::vector<char> gauge;              // pose k fixed?
  std::vector<std::pair<int, int>> ends;  // per graph edge: (pose a, pose b), (−1, −1) if not pose–pose
};

PoseIndex index_poses(const PoseGraph& g, const std::vector<std::int64_t>& gauge_ids) {
  PoseIndex ix;
  ix.pose_of.assign(g.vertices().size(), -1);
  for (std::size_t i = 0; i < g.vertices().size(); ++i) {
    if (!is_pose(g.vertices()[i])) continue;
    ix.pose_of[i] = static_cast<int>(ix.vertex.size());
    ix.vertex.push_back(i);
  }
  ix.gauge.assign(ix.vertex.size(), 0);
  for (std::int64_t id : gauge_ids) {
    const int k = ix.pose_of[*g.index_of(id)];
    if (k >= 0) ix.gauge[k] = 1;
  }
  for (const GraphEdge& e : g.edges) {
    if (!is_pose_edge(e)) {
      ix.ends.emplace_back(-1, -1);
      continue;
    }
    ix.ends.emplace_back(ix.pose_of[*g.index_of(e.from)], ix.pose_of[*g.index_of(e.to)]);
  }
  return ix;
}

// Breadth-first spanning tree from the gauge poses over pose–pose edges. Fills parent edge
// per pose (−1 for roots/unreached) and the visiting order.
void spanning_tree(const PoseGraph& g, const PoseIndex& ix, std::vector<int>* parent_edge, std::vector<int>* order) {
  const std::size_t n = ix.vertex.size();
  // Incident edges of pose a, ascending: incident[start[a] .. start[a + 1]) (counting sort).
  std::vector<int> start(n + 1, 0), incident;
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const auto [a, b] = ix.ends[e];
    if (a < 0 || a == b) continue;
    ++start[a + 1], ++start[b + 1];
  }
  for (std::size_t k = 0; k < n; ++k) start[k + 1] += start[k];
  incident.resize(start[n]);
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t e = 0; e < g.edges.size(); ++e) {
      const auto [a, b] = ix.ends[e];
      if (a < 0 || a == b) continue;
      incident[fill[a]++] = static_cast<int>(e);
      incident[fill[b]++] = static_cast<int>(e);
    }
  }
  parent_edge->assign(n, -1);
  std::vector<char> seen(n, 0);
  // The visiting order is the queue: poses are appended when reached, visited front to back.
  order->clear();
  order->reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    if (ix.gauge[k]) seen[k] = 1, order->push_back(static_cast<int>(k));
  for (std::size_t head = 0; head < order->size(); ++head) {
    const int a = (*order)[head];
    for (int q = start[a]; q < start[a + 1]; ++q) {
      const int e = incident[q];
      const int b = ix.ends[e].first == a ? ix.ends[e].second : ix.ends[e].first;
      if (seen[b]) continue;
      seen[b] = 1;
      (*parent_edge)[b] = e;
      order->push_back(b);
    }
  }
}

// Composes poses along the spanning tree (each child from its parent through the tree edge).
void compose_along_tree(PoseGraph& g, const PoseIndex& ix, const std::vector<int>& parent_edge,
                        const std::vector<int>& order) {
  for (int k : order) {
    const int e = parent_edge[k];
    if (e < 0) continue;
    const GraphEdge& edge = g.edges[e];
    GraphVertex& child = g.vertex_at(ix.vertex[k]);
    const bool forward = g.vertices()[ix.vertex[k]].id == edge.to;  // parent is `from`
    const GraphVertex& parent = g.vertex(forward ? edge.from : edge.to);
    if (edge.kind == EdgeKind::kPose2Pose2) {
      child.pose2 = forward ? parent.pose2 * edge.pose2 : parent.pose2 * edge.pose2.inverse();
    } else {
      child.pose3 = forward ? parent.pose3 * edge.pose3 : parent.pose3 * edge.pose3.inverse();
    }
    child.has_estimate = true;
  }
}

// Landmarks (and anything unreached) from the first observing pose.
// (A pose-only graph whose poses all have estimates has nothing to complete: no pass.)
void initialize_points(PoseGraph& g) {
  bool missing = false;
  for (std::size_t i = 0; i < g.vertices().size(); ++i) {
    GraphVertex& v = g.vertex_at(i);
    if (!is_pose(v)) v.has_estimate = false;
    missing = missing || !v.has_estimate;
  }
  if (missing) complete_estimates_by_odometry(g);
}

// The unknowns of the initialization's linear systems: the non-gauge poses, numbered in
// elimination order (so that the Cholesky factorizes a system as stored): the shared vertex
// order if given, else a new one; and the block pattern of their normal equations. Computed
// once and shared by every system over the same poses (2D: orientations and positions).
struct PoseLayout {
  std::vector<int> unknown;                // pose k → unknown (−1 for gauge poses)
  int n = 0;                               // number of unknowns
  std::vector<std::pair<int, int>> pattern;  // off-diagonal blocks (unknown, unknown)
};

PoseLayout pose_layout(const PoseIndex& ix, const std::vector<std::pair<int, int>>& edges, const InitOptions& o) {
  PoseLayout l;
  std::vector<int> free_index(ix.vertex.size(), -1);
  for (std::size_t k = 0; k < ix.vertex.size(); ++k)
    if (!ix.gauge[k]) free_index[k] = l.n++;
  std::vector<std::pair<int, int>> free_edges;
  for (const auto& [a, b] : edges)
    if (free_index[a] >= 0 && free_index[b] >= 0 && a != b) free_edges.emplace_back(free_index[a], free_index[b]);
  EliminationOrder order;
  if (!o.vertex_order.order.empty()) {
    order.method = o.vertex_order.method;
    for (int v : o.vertex_order.order) {
      const int pose = ix.pose_of.at(static_cast<std::size_t>(v));
      if (pose >= 0 && free_index[pose] >= 0) order.order.push_back(free_index[pose]);
    }
    order = postordered(l.n, free_edges, std::move(order));
  } else {
    order = compute_elimination_order(l.n, free_edges, o.ordering);
  }
  std::vector<int> position(l.n);
  for (int p = 0; p < l.n; ++p) position[order.order[p]] = p;
  l.unknown.assign(ix.vertex.size(), -1);
  for (std::size_t k = 0; k < ix.vertex.size(); ++k)
    if (free_index[k] >= 0) l.unknown[k] = position[free_index[k]];
  l.pattern.reserve(free_edges.size());
  for (const auto& [a, b] : free_edges) l.pattern.emplace_back(position[a], position[b]);
  return l;
}

// The normal equations of a linear least-squares problem over the non-gauge poses, with
// B×B blocks and up to three right-hand sides. Gauge (known) poses are eliminated into the
// right-hand side. The pattern, and its symbolic factorization, are fixed at construction.
template <int B>
class PoseSystem {
 public:
  using Block = Eigen::Matrix<double, B, B>;
  using Rhs = Eigen::Matrix<double, B, Eigen::Dynamic, (B == 1 ? Eigen::RowMajor : Eigen::ColMajor), B, 3>;

  /// same_pattern: a system over the same layout, whose block pattern is taken as is.
  PoseSystem(const PoseLayout& layout, int rhs, const InitOptions& o, InitSummary& summary,
             const BlockSparseMatrix* same_pattern = nullptr)
      : unknown_(layout.unknown), summary_(summary) {
    const auto t0 = std::chrono::steady_clock::now();
    A_ = same_pattern ? BlockSparseMatrix(*same_pattern, std::vector<int>(layout.n, B))
                      : BlockSparseMatrix(std::vector<int>(layout.n, B), layout.pattern);
    B_ = Eigen::MatrixXd::Zero(A_.rows(), rhs);
    chol_ = make_sparse_cholesky(o.linear_solver, o.ordering, o.threads);
    chol_->analyze_sharing(A_, summary_.symbolic);  // the pattern analysis of an earlier system over the same poses
    if (!chol_->stats().shared_analysis) ++summary_.analyses;
    if (SharedSymbolic shared = chol_->shared_symbolic()) summary_.symbolic = std::move(shared);
    summary_.time_analyze_s += seconds_since(t0);
  }
  int unknown(int pose) const { return unknown_[pose]; }
  const BlockSparseMatrix& matrix() const { return A_; }
  /// Clears the values for a new system with the same pattern and `rhs` right-hand sides.
  void reset(int rhs) {
    A_.set_zero();
    B_ = Eigen::MatrixXd::Zero(A_.rows(), rhs);
  }
  /// Adds the term ‖Ma x_a + Mb x_b − c‖²_W (one column of c per right-hand side); x_known
  /// are the values of gauge poses, used when a or b is not an unknown.
  void add(int a, const Block& Ma, int b, const Block& Mb, const Rhs& c, const Block& W, const Rhs& xa_known,
           const Rhs& xb_known) {
    const int ua = unknown_[a], ub = unknown_[b];
    Rhs rhs = c;
    if (ua < 0) rhs -= Ma * xa_known;
    if (ub < 0) rhs -= Mb * xb_known;
    const Block MaW = Ma.transpose() * W, MbW = Mb.transpose() * W;
    if (ua >= 0) {
      block(ua, ua) += MaW * Ma;
      B_.middleRows<B>(ua * B) += MaW * rhs;
    }
    if (ub >= 0) {
      block(ub, ub) += MbW * Mb;
      B_.middleRows<B>(ub * B) += MbW * rhs;
    }
    if (ua >= 0 && ub >= 0 && ua != ub) {  // lower triangle: block (larger, smaller)
      if (ua > ub) {
        block(ua, ub) += MaW * Mb;
      } else {
        block(ub, ua) += MbW * Ma;
      }
    }
  }
  Eigen::MatrixXd solve() {
    if (A_.rows() == 0) return B_;
    const auto t0 = std::chrono::steady_clock::now();
    if (!chol_->factorize(A_))
      throw NumericalError("initialization: the linear system is singular (is every pose connected to a gauge vertex?)");
    Eigen::MatrixXd x = chol_->solve(B_);
    summary_.time_solve_s += seconds_since(t0);
    return x;
  }

 private:
  Eigen::Map<Block, 0, Eigen::OuterStride<>> block(int i, int j) {
    return Eigen::Map<Block, 0, Eigen::OuterStride<>>(A_.values().data() + A_.block_offset(i, j),
                                                      Eigen::OuterStride<>(A_.leading_dim(j)));
  }
  const std::vector<int>& unknown_;
  BlockSparseMatrix A_;
  Eigen::MatrixXd B_;
  std::unique_ptr<SparseCholesky> chol_;
  InitSummary& summary_;
};

std::vector<std::pair<int, int>> pose_pairs(const PoseIndex& ix) {
  std::vector<std::pair<int, int>> p;
  for (const auto& e : ix.ends)
    if (e.first >= 0 && e.first != e.second) p.push_back(e);
  return p;
}

// ---- 2D: LAGO-style orientations, then positions.
void linear_2d(PoseGraph& g, const PoseIndex& ix, const InitOptions& o, InitSummary& summary) {
  auto t = std::chrono::steady_clock::now();
  std::vector<int> parent, order;
  spanning_tree(g, ix, &parent, &order);
  const std::size_t n = ix.vertex.size();
  // Unwrapped tree orientations.
  std::vector<double> tree_theta(n, 0.0);
  for (std::size_t k = 0; k < n; ++k)
    if (ix.gauge[k]) tree_theta[k] = g.vertices()[ix.vertex[k]].pose2.theta();
  for (int k : order) {
    const int e = parent[k];
    if (e < 0) continue;
    const GraphEdge& edge = g.edges[e];
    const bool forward = ix.ends[e].second == k;
    const int p = forward ? ix.ends[e].first : ix.ends[e].second;
    tree_theta[k] = tree_theta[p] + (forward ? edge.pose2.theta() : -edge.pose2.theta());
  }
  summary.time_tree_s += seconds_since(t);
  const auto pairs = pose_pairs(ix);
  using Scalar1 = Eigen::Matrix<double, 1, 1>;
  // A one-column right-hand side built as such (a 1×1 matrix converted to it draws GCC 12's
  // false -Warray-bounds in Eigen's packet copy).
  const auto row1 = [](double v) {
    PoseSystem<1>::Rhs r(1, 1);
    r(0, 0) = v;
    return r;
  };
  auto t_layout = std::chrono::steady_clock::now();
  const PoseLayout layout = pose_layout(ix, pairs, o);
  summary.time_analyze_s += seconds_since(t_layout);
  PoseSystem<1> theta_sys(layout, 1, o, summary);
  t = std::chrono::steady_clock::now();
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const auto [a, b] = ix.ends[e];
    if (a < 0 || a == b) continue;
    const GraphEdge& edge = g.edges[e];
    const double delta = edge.pose2.theta();
    const double wraps = std::round((tree_theta[b] - tree_theta[a] - delta) / (2.0 * kPi));
    // Marginal information of θ: 1 / (Ω⁻¹)_θθ.
    const Eigen::Matrix3d omega = edge.information.topLeftCorner<3, 3>();
    const double w = 1.0 / omega.inverse()(2, 2);
    theta_sys.add(a, Scalar1(-1.0), b, Scalar1(1.0), row1(delta + 2.0 * kPi * wraps), Scalar1(w), row1(tree_theta[a]),
                  row1(tree_theta[b]));
  }
  summary.time_assemble_s += seconds_since(t);
  const Eigen::MatrixXd theta = theta_sys.solve();
  std::vector<double> th(n);
  for (std::size_t k = 0; k < n; ++k) th[k] = ix.gauge[k] ? tree_theta[k] : theta(theta_sys.unknown(k), 0);

  // Positions given θ: g2o's translation error R_zᵀ(R_aᵀ(p_b − p_a) − t_z) has weight
  // (R_a R_z) Ω_xy (R_a R_z)ᵀ. When every Ω_xy is isotropic (s I: M3500, city10000, ...), that
  // weight is s I and the system is the weighted Laplacian ⊗ I₂: the θ system's pattern, order
  // and symbolic analysis solve it with x and y as two right-hand sides, 1×1 blocks.
  bool isotropic = true;
  for (std::size_t e = 0; e < g.edges.size() && isotropic; ++e) {
    const auto [a, b] = ix.ends[e];
    if (a < 0 || a == b) continue;
    const Eigen::MatrixXd& om = g.edges[e].information;
    isotropic = om(0, 1) == 0.0 && om(1, 0) == 0.0 && om(0, 0) == om(1, 1);
  }
  t = std::chrono::steady_clock::now();
  Eigen::MatrixXd pos;
  if (isotropic) {
    using Row2 = PoseSystem<1>::Rhs;
    theta_sys.reset(2);
    for (std::size_t e = 0; e < g.edges.size(); ++e) {
      const auto [a, b] = ix.ends[e];
      if (a < 0 || a == b) continue;
      const GraphEdge& edge = g.edges[e];
      const Eigen::Vector2d c = SO2(th[a]).matrix() * edge.pose2.translation();
      const Eigen::Vector2d pa = g.vertices()[ix.vertex[a]].pose2.translation();
      const Eigen::Vector2d pb = g.vertices()[ix.vertex[b]].pose2.translation();
      theta_sys.add(a, Scalar1(-1.0), b, Scalar1(1.0), Row2(c.transpose()), Scalar1(edge.information(0, 0)),
                    Row2(pa.transpose()), Row2(pb.transpose()));
    }
    summary.time_assemble_s += seconds_since(t);
    pos = theta_sys.solve();  // row u: (x, y) of unknown u
  } else {
    PoseSystem<2> pos_sys(layout, 1, o, summary, &theta_sys.matrix());
    t = std::chrono::steady_clock::now();
    const Eigen::Matrix2d I2 = Eigen::Matrix2d::Identity();
    for (std::size_t e = 0; e < g.edges.size(); ++e) {
      const auto [a, b] = ix.ends[e];
      if (a < 0 || a == b) continue;
      const GraphEdge& edge = g.edges[e];
      const Eigen::Matrix2d Ra = SO2(th[a]).matrix();
      const Eigen::Matrix2d M = Ra * edge.pose2.rotation().matrix();
      const Eigen::Matrix2d W = M * edge.information.topLeftCorner<2, 2>() * M.transpose();
      pos_sys.add(a, -I2, b, I2, Ra * edge.pose2.translation(), W, g.vertices()[ix.vertex[a]].pose2.translation(),
                  g.vertices()[ix.vertex[b]].pose2.translation());
    }
    summary.time_assemble_s += seconds_since(t);
    const Eigen::MatrixXd stacked = pos_sys.solve();  // rows 2u, 2u + 1: (x, y) of unknown u
    pos = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>(stacked.data(),
                                                                                       stacked.rows() / 2, 2);
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (ix.gauge[k]) continue;
    GraphVertex& v = g.vertex_at(ix.vertex[k]);
    v.pose2 = SE2(SO2(th[k]), pos.row(layout.unknown[k]).transpose());
    v.has_estimate = true;
  }
}

Eigen::Matrix3d project_to_so3(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

// ---- 3D: chordal relaxation of rotations, then positions.
void chordal_3d(PoseGraph& g, const PoseIndex& ix, const InitOptions& o, InitSummary& summary) {
  const std::size_t n = ix.vertex.size();
  const auto pairs = pose_pairs(ix);
  // Unknowns per pose: x = (row k of R)ᵀ for k = 0, 1, 2 as three right-hand sides.
  // Edge R_b = R_a Z ⇒ row: x_b − Zᵀ x_a = 0.
  auto t = std::chrono::steady_clock::now();
  const PoseLayout layout = pose_layout(ix, pairs, o);
  summary.time_analyze_s += seconds_since(t);
  PoseSystem<3> sys(layout, 3, o, summary);
  t = std::chrono::steady_clock::now();
  const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const auto [a, b] = ix.ends[e];
    if (a < 0 || a == b) continue;
    const GraphEdge& edge = g.edges[e];
    const Eigen::Matrix3d Zt = edge.pose3.rotation().matrix().transpose();
    const double w = edge.information.bottomRightCorner<3, 3>().trace() / 3.0;
    // Columns of Rᵀ are the rows of R: the three right-hand sides.
    sys.add(a, -Zt, b, I3, Eigen::Matrix3d::Zero(), w * I3,
            g.vertices()[ix.vertex[a]].pose3.rotation().matrix().transpose(),
            g.vertices()[ix.vertex[b]].pose3.rotation().matrix().transpose());
  }
  summary.time_assemble_s += seconds_since(t);
  const Eigen::MatrixXd X = sys.solve();
  std::vector<Eigen::Matrix3d> R(n);
  for (std::size_t k = 0; k < n; ++k) {
    R[k] = ix.gauge[k] ? g.vertices()[ix.vertex[k]].pose3.rotation().matrix()
                       : project_to_so3(X.middleRows<3>(3 * sys.unknown(static_cast<int>(k))).transpose());
  }
  t = std::chrono::steady_clock::now();
  sys.reset(1);  // positions: same pattern, same symbolic factorization
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const auto [a, b] = ix.ends[e];
    if (a < 0 || a == b) continue;
    const GraphEdge& edge = g.edges[e];
    const Eigen::Matrix3d M = R[a] * edge.pose3.rotation().matrix();
    const Eigen::Matrix3d W = M * edge.information.topLeftCorner<3, 3>() * M.transpose();
    sys.add(a, -I3, b, I3, R[a] * edge.pose3.translation(), W, g.vertices()[ix.vertex[a]].pose3.translation(),
            g.vertices()[ix.vertex[b]].pose3.translation());
  }
  summary.time_assemble_s += seconds_since(t);
  const Eigen::MatrixXd pos = sys.solve();
  for (std::size_t k = 0; k < n; ++k) {
    if (ix.gauge[k]) continue;
    GraphVertex& v = g.vertex_at(ix.vertex[k]);
    v.pose3 = SE3(SO3::from_matrix(R[k]), pos.middleRows<3>(3 * sys.unknown(static_cast<int>(k))));
    v.has_estimate = true;
  }
}

}  // namespace

const char* to_string(InitMethod m) {
  switch (m) {
    case InitMethod::kNone: return "none";
    case InitMethod::kOdometry: return "odometry";
    case InitMethod::kSpanningTree: return "spanning-tree";
    case InitMethod::kLinear: return "linear";
    case InitMethod::kChordal: return "chordal";
    case InitMethod::kAuto: return "auto";
    case InitMethod::kSgd: return "sgd";
    case InitMethod::kToro: return "toro";
    case InitMethod::kRelax: return "relax";
    case InitMethod::kMlr: return "mlr";
  }
  return "?";
}

InitMethod parse_init_method(const std::string& s) {
  for (auto m : {InitMethod::kNone, InitMethod::kOdometry, InitMethod::kSpanningTree, InitMethod::kLinear,
                 InitMethod::kChordal, InitMethod::kAuto, InitMethod::kSgd, InitMethod::kToro, InitMethod::kRelax,
                 InitMethod::kMlr})
    if (s == to_string(m)) return m;
  throw InputError("", 0, "init", "unknown initialization '" + s + "' (none, odometry, spanning-tree, linear, chordal, auto, sgd, toro, relax, mlr)");
}

InitSummary initialize_pose_graph(PoseGraph& g, InitMethod method, const std::vector<std::int64_t>& gauge,
                                  const InitOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  for (std::int64_t id : gauge)
    if (!g.index_of(id)) throw InputError(g.source, 0, "gauge", "gauge vertex " + std::to_string(id) + " is not in the graph");
  if (gauge.empty() && !g.vertices().empty() && method != InitMethod::kNone)
    throw InputError(g.source, 0, "gauge", "no gauge vertex: nothing anchors the initialization");
  InitSummary s;
  s.requested = method;
  const int dim = g.dimension();
  if (method == InitMethod::kAuto) method = dim == 3 ? InitMethod::kChordal : InitMethod::kLinear;
  s.used = method;
  if (method == InitMethod::kLinear && dim != 2)
    throw InputError(g.source, 0, "init", "linear (LAGO) initialization is for 2D graphs; use chordal in 3D");
  if (method == InitMethod::kChordal && dim != 3)
    throw InputError(g.source, 0, "init", "chordal initialization is for 3D graphs; use linear in 2D");

  if (is_relaxer_init(method)) {
    s.notes = relaxer_initialize(g, method);
  } else if (method == InitMethod::kOdometry) {
    for (std::size_t i = 0; i < g.vertices().size(); ++i) g.vertex_at(i).has_estimate = false;
    for (std::int64_t id : gauge) g.vertex_at(*g.index_of(id)).has_estimate = true;
    complete_estimates_by_odometry(g);
  } else if (method != InitMethod::kNone) {
    const PoseIndex ix = index_poses(g, gauge);
    if (method == InitMethod::kSpanningTree) {
      std::vector<int> parent, order;
      spanning_tree(g, ix, &parent, &order);
      compose_along_tree(g, ix, parent, order);
    } else if (method == InitMethod::kLinear) {
      linear_2d(g, ix, options, s);
    } else {
      chordal_3d(g, ix, options, s);
    }
    const auto t_points = std::chrono::steady_clock::now();
    initialize_points(g);
    s.time_points_s = seconds_since(t_points);
  }
  s.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s;
}

}  // namespace slamkit
