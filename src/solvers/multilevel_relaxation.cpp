#include "slamkit/solvers/multilevel_relaxation.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <unordered_map>

#include "slamkit/solvers/relaxer_pose_traits.h"
#include "slamkit/core/error.h"

namespace slamkit {
namespace {

// One level of the hierarchy: a block-sparse symmetric system over n nodes.
template <int D>
struct Level {
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  int n = 0;
  std::vector<Mat> diag, diag_inv;
  std::vector<std::pair<int, int>> off_ends;  // (i, j), i ≠ j: block A_ij = off[k], A_ji = off[k]ᵀ
  std::vector<Mat> off;
  std::vector<std::vector<std::pair<int, bool>>> adjacent;  // node → (off block, node is its first end)
  std::vector<char> fixed;
  std::vector<Mat> to_coarse;  // P block of each node into its parent group (zero when fixed)
  std::unordered_map<std::uint64_t, int> off_index;

  void reset(int size) {
    n = size;
    diag.assign(n, Mat::Zero());
    off_ends.clear();
    off.clear();
    off_index.clear();
    fixed.assign(n, 0);
  }
  void add(int i, int j, const Mat& B) {  // A_ij += B (and A_ji += Bᵀ)
    if (i == j) {
      diag[i] += B + B.transpose();
      return;
    }
    const bool swap = i > j;
    const std::uint64_t key = (std::uint64_t(swap ? j : i) << 32) | std::uint64_t(swap ? i : j);
    auto [it, inserted] = off_index.emplace(key, static_cast<int>(off.size()));
    if (inserted) {
      off_ends.emplace_back(swap ? j : i, swap ? i : j);
      off.push_back(Mat::Zero());
    }
    off[it->second] += swap ? Mat(B.transpose()) : B;
  }
  void finish() {
    adjacent.assign(n, {});
    for (std::size_t k = 0; k < off_ends.size(); ++k) {
      adjacent[off_ends[k].first].emplace_back(static_cast<int>(k), true);
      adjacent[off_ends[k].second].emplace_back(static_cast<int>(k), false);
    }
    diag_inv.resize(n);
    for (int i = 0; i < n; ++i) {
      if (fixed[i] || !(diag[i].diagonal().minCoeff() > 0)) {
        fixed[i] = 1;  // a fixed node, or a group made only of fixed nodes: no unknowns
        diag_inv[i].setZero();
      } else {
        diag_inv[i] = diag[i].ldlt().solve(Mat::Identity());
      }
    }
  }
  Vec row_times(int i, const std::vector<Vec>& x) const {  // Σ_{j≠i} A_ij x_j
    Vec s = Vec::Zero();
    for (const auto& [k, first] : adjacent[i]) {
      if (first) s += off[k] * x[off_ends[k].second];
      else s += off[k].transpose() * x[off_ends[k].first];
    }
    return s;
  }
  void smooth(const std::vector<Vec>& b, std::vector<Vec>& x, int sweeps) const {
    for (int s = 0; s < sweeps; ++s) {
      for (int i = 0; i < n; ++i)
        if (!fixed[i]) x[i] = diag_inv[i] * (b[i] - row_times(i, x));
      for (int i = n - 1; i >= 0; --i)  // symmetric sweep: forward then backward
        if (!fixed[i]) x[i] = diag_inv[i] * (b[i] - row_times(i, x));
    }
  }
  std::vector<Vec> residual(const std::vector<Vec>& b, const std::vector<Vec>& x) const {
    std::vector<Vec> r(n);
    for (int i = 0; i < n; ++i) r[i] = fixed[i] ? Vec::Zero() : Vec(b[i] - diag[i] * x[i] - row_times(i, x));
    return r;
  }
  void solve_directly(const std::vector<Vec>& b, std::vector<Vec>& x) const {
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n * D, n * D);
    Eigen::VectorXd rhs(n * D);
    for (int i = 0; i < n; ++i) {
      A.block<D, D>(i * D, i * D) = fixed[i] ? Mat(Mat::Identity()) : diag[i];
      rhs.segment<D>(i * D) = fixed[i] ? Vec::Zero() : b[i];
    }
    for (std::size_t k = 0; k < off.size(); ++k) {
      const auto [i, j] = off_ends[k];
      if (fixed[i] || fixed[j]) continue;
      A.block<D, D>(i * D, j * D) = off[k];
      A.block<D, D>(j * D, i * D) = off[k].transpose();
    }
    const Eigen::VectorXd sol = A.ldlt().solve(rhs);
    for (int i = 0; i < n; ++i) x[i] = sol.segment<D>(i * D);
  }
};

template <int D>
class Multigrid {
 public:
  using T = detail::RelaxerPose<D>;
  using Pose = typename T::Pose;
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;

  Multigrid(PoseGraph& g, const RelaxerGraph& rg, const MultilevelOptions& o) : g_(g), rg_(rg), o_(o) {
    int n = static_cast<int>(rg.vertex.size());
    while (true) {
      levels_.emplace_back();
      if (n <= o.coarsest_nodes) break;
      n = (n + 1) / 2;
    }
  }

  // One linearization and V-cycles; returns the max |δ| applied.
  double iterate() {
    linearize();
    Level<D>& fine = levels_[0];
    std::vector<Vec> x(fine.n, Vec::Zero());
    double bnorm = 0;
    for (const Vec& v : b0_) bnorm += v.squaredNorm();
    bnorm = std::sqrt(bnorm);
    for (int c = 0; c < o_.max_cycles; ++c) {
      v_cycle(0, b0_, x);
      double rn = 0;
      for (const Vec& v : fine.residual(b0_, x)) rn += v.squaredNorm();
      if (std::sqrt(rn) <= o_.cycle_tolerance * bnorm) break;
    }
    double change = 0;
    for (int i = 0; i < fine.n; ++i) {
      if (fine.fixed[i] || !x[i].allFinite()) continue;
      Pose& p = T::pose(g_.vertex_at(rg_.vertex[i]));
      p = p.plus(x[i]);
      change = std::max(change, x[i].cwiseAbs().maxCoeff());
    }
    return change;
  }

 private:
  void linearize() {
    Level<D>& L = levels_[0];
    const int n = static_cast<int>(rg_.vertex.size());
    L.reset(n);
    for (int i = 0; i < n; ++i) L.fixed[i] = rg_.gauge[i];
    b0_.assign(n, Vec::Zero());
    for (std::size_t e = 0; e < g_.edges.size(); ++e) {
      const GraphEdge& edge = g_.edges[e];
      const auto [a, b] = rg_.ends[e];
      Mat Ja, Jb;
      const Vec err = T::error(T::measurement(edge), T::pose(g_.vertices()[rg_.vertex[a]]),
                               T::pose(g_.vertices()[rg_.vertex[b]]), &Ja, &Jb);
      const Mat& O = edge.information;
      L.diag[a] += Ja.transpose() * O * Ja;
      L.diag[b] += Jb.transpose() * O * Jb;
      L.add(a, b, Ja.transpose() * O * Jb);
      b0_[a] -= Ja.transpose() * O * err;
      b0_[b] -= Jb.transpose() * O * err;
    }
    L.finish();
    // Representative poses: a group is represented by its first member.
    std::vector<Pose> rep(n);
    for (int i = 0; i < n; ++i) rep[i] = T::pose(g_.vertices()[rg_.vertex[i]]);
    for (std::size_t l = 0; l + 1 < levels_.size(); ++l) {
      Level<D>& F = levels_[l];
      Level<D>& C = levels_[l + 1];
      F.to_coarse.resize(F.n);
      for (int i = 0; i < F.n; ++i)
        F.to_coarse[i] = F.fixed[i] ? Mat(Mat::Zero()) : Mat(rep[i].between(rep[i / 2 * 2]).adjoint());
      C.reset((F.n + 1) / 2);
      for (int i = 0; i < F.n; ++i) {
        const Mat& P = F.to_coarse[i];
        C.diag[i / 2] += P.transpose() * F.diag[i] * P;
      }
      for (std::size_t k = 0; k < F.off.size(); ++k) {
        const auto [i, j] = F.off_ends[k];
        C.add(i / 2, j / 2, F.to_coarse[i].transpose() * F.off[k] * F.to_coarse[j]);
      }
      for (int c = 0; c < C.n; ++c) C.fixed[c] = F.fixed[2 * c] && (2 * c + 1 >= F.n || F.fixed[2 * c + 1]);
      C.finish();
      std::vector<Pose> coarse_rep(C.n);
      for (int c = 0; c < C.n; ++c) coarse_rep[c] = rep[2 * c];
      rep = std::move(coarse_rep);
    }
  }

  void v_cycle(std::size_t l, const std::vector<Vec>& b, std::vector<Vec>& x) {
    const Level<D>& L = levels_[l];
    if (l + 1 == levels_.size()) {
      L.solve_directly(b, x);
      return;
    }
    L.smooth(b, x, o_.pre_smoothing);
    const std::vector<Vec> r = L.residual(b, x);
    const Level<D>& C = levels_[l + 1];
    std::vector<Vec> bc(C.n, Vec::Zero()), xc(C.n, Vec::Zero());
    for (int i = 0; i < L.n; ++i) bc[i / 2] += L.to_coarse[i].transpose() * r[i];
    v_cycle(l + 1, bc, xc);
    for (int i = 0; i < L.n; ++i) x[i] += L.to_coarse[i] * xc[i / 2];
    L.smooth(b, x, o_.post_smoothing);
  }

  PoseGraph& g_;
  const RelaxerGraph& rg_;
  MultilevelOptions o_;
  std::vector<Level<D>> levels_;
  std::vector<Vec> b0_;
};

}  // namespace

RelaxerSummary optimize_multilevel(PoseGraph& g, const MultilevelOptions& options) {
  if (options.coarsest_nodes < 1 || options.max_cycles < 1 || options.pre_smoothing < 0 || options.post_smoothing < 0)
    throw InputError("", 0, "mlr", "coarsest_nodes and max_cycles must be ≥ 1, smoothing sweeps ≥ 0");
  const RelaxerGraph rg = make_relaxer_graph(g);
  RelaxerSummary s;
  if (rg.dimension == 2) {
    Multigrid<3> mg(g, rg, options);
    s = run_relaxer(g, "mlr", options.stop, [&](int) { return mg.iterate(); }, [] {});
  } else {
    Multigrid<6> mg(g, rg, options);
    s = run_relaxer(g, "mlr", options.stop, [&](int) { return mg.iterate(); }, [] {});
  }
  s.num_loop_closures = rg.num_loop_closures;
  return s;
}

}  // namespace slamkit
