#include "sgd_chain_2d.h"
#include "relaxer_math_2d.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slamkit::detail {

ChainSgd2D::ChainSgd2D(const PoseGraph& g, const RelaxerGraph& rg, std::vector<int> chain)
    : chain_(std::move(chain)), vertex_(rg.vertex), n_(static_cast<int>(chain_.size())) {
  std::vector<int> position(n_);
  for (int p = 0; p < n_; ++p) position[chain_[p]] = p;
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const GraphEdge& ge = g.edges[e];
    edges_.push_back({position[rg.ends[e].first], position[rg.ends[e].second],
                      Eigen::Vector3d(ge.pose2.x(), ge.pose2.y(), ge.pose2.theta()), std::cos(ge.pose2.theta()),
                      std::sin(ge.pose2.theta()), 0.5 * (ge.information + ge.information.transpose())});
  }
  // Unwrapped orientations along the chain, so that increments stay small.
  pose0_.resize(n_);
  for (int p = 0; p < n_; ++p) {
    const SE2& x = g.vertices()[vertex_[chain_[p]]].pose2;
    pose0_[p] = Eigen::Vector3d(x.x(), x.y(), x.theta());
    if (p > 0) pose0_[p].z() = pose0_[p - 1].z() + wrap_angle(x.theta() - pose0_[p - 1].z());
  }
  wsum_.assign(n_, Eigen::Vector3d::Zero());
  tree_.assign(n_ + 2, Node());
}

Eigen::Vector3d ChainSgd2D::query(int p) const {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  for (int k = p + 1; k > 0; k -= k & -k) a += tree_[k].s1, b += tree_[k].s2;
  return pose0_[p] + wsum_[p].cwiseProduct(a) + b;
}

void ChainSgd2D::range_add(int lo, int hi, const Eigen::Vector3d& c) {
  const Eigen::Vector3d before = lo > 0 ? Eigen::Vector3d(c.cwiseProduct(wsum_[lo - 1])) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d after = c.cwiseProduct(wsum_[hi]);
  for (int k = lo + 1; k <= n_ + 1; k += k & -k) tree_[k].s1 += c, tree_[k].s2 -= before;
  for (int k = hi + 2; k <= n_ + 1; k += k & -k) tree_[k].s1 -= c, tree_[k].s2 += after;
}

void ChainSgd2D::range_add_theta(int hi, double c) {
  for (int k = 2; k <= n_ + 1; k += k & -k) tree_[k].s1.z() += c;  // from position 1: W(0) = 0
  for (int k = hi + 2; k <= n_ + 1; k += k & -k) tree_[k].s1.z() -= c, tree_[k].s2.z() += c * wsum_[hi].z();
}

double ChainSgd2D::iterate(int iteration, const std::vector<int>& order) {
  // Preconditioner: M_k = Σ diag W over the edges whose range covers k (a difference array).
  // Second phase: + uᵀ W_xy u on the θ increments 1..a (the coupling's diagonal).
  const bool phase = phase_.start > 0 && iteration > phase_.start;
  std::vector<Eigen::Vector3d> m(n_ + 1, Eigen::Vector3d::Zero());
  gamma_.setConstant(std::numeric_limits<double>::infinity());
  for (const Edge& e : edges_) {
    const double ca = std::cos(pose0_[e.pa].z()), sa = std::sin(pose0_[e.pa].z());
    const Eigen::Matrix3d W = rotate_information(e.info, ca * e.cz - sa * e.sz, sa * e.cz + ca * e.sz);
    const Eigen::Vector3d w = W.diagonal();
    gamma_ = gamma_.cwiseMin(w);
    const int lo = std::min(e.pa, e.pb) + 1, hi = std::max(e.pa, e.pb);
    m[lo] += w;
    m[hi + 1] -= w;
    if (phase && e.pa > 0) {
      const Eigen::Vector2d rz = rot2(ca, sa) * e.z.head<2>();
      const Eigen::Vector2d u(-rz.y(), rz.x());
      const double q = u.dot(W.topLeftCorner<2, 2>() * u);
      m[1].z() += q;
      m[e.pa + 1].z() -= q;
    }
  }
  Eigen::Vector3d run = Eigen::Vector3d::Zero();
  for (int p = 0; p < n_; ++p) {
    run += m[p];
    for (int i = 0; i < 3; ++i) {
      const double w = p > 0 && run[i] > 0 ? 1.0 / run[i] : 0.0;
      wsum_[p][i] = (p > 0 ? wsum_[p - 1][i] : 0.0) + w;
    }
  }
  std::fill(tree_.begin(), tree_.end(), Node());
  if (phase) {  // C: the quantile of the path-length factors l / Σ_path 1/M
    std::vector<double> c(edges_.size());
    for (int i = 0; i < 3; ++i) {
      for (std::size_t k = 0; k < edges_.size(); ++k) {
        const int lo = std::min(edges_[k].pa, edges_[k].pb) + 1, hi = std::max(edges_[k].pa, edges_[k].pb);
        c[k] = (hi - lo + 1) / (wsum_[hi][i] - wsum_[lo - 1][i]);
      }
      const auto q = c.begin() + static_cast<std::ptrdiff_t>(phase_.quantile * static_cast<double>(c.size() - 1));
      std::nth_element(c.begin(), q, c.end());
      phase_c_[i] = *q;
    }
  }
  const double tau = phase ? phase_.t0 + (iteration - phase_.start) : iteration;
  double change = 0.0;
  for (int k : order) {
    const Edge& e = edges_[k];
    const Eigen::Vector3d pa = query(e.pa), pb = query(e.pb);
    const double ca = std::cos(pa.z()), sa = std::sin(pa.z());
    const Eigen::Vector2d rz = rot2(ca, sa) * e.z.head<2>();  // R(θa) z_xy
    Eigen::Vector3d r;
    r.head<2>() = pa.head<2>() + rz - pb.head<2>();
    r.z() = wrap_angle(pa.z() + e.z.z() - pb.z());
    const Eigen::Matrix3d W = rotate_information(e.info, ca * e.cz - sa * e.sz, sa * e.cz + ca * e.sz);
    const Eigen::Vector3d d = 2.0 * W * r;
    const int lo = std::min(e.pa, e.pb) + 1, hi = std::max(e.pa, e.pb);
    const double l = hi - lo + 1;
    // Increments between a and b move b (a before b on the chain) or a (b before a).
    const double sign = e.pa < e.pb ? 1.0 : -1.0;
    if (phase && e.pa > 0) {  // coupling: ∂r_xy/∂θ_a = u, a step on the θ increments 1..a
      const Eigen::Vector2d u(-rz.y(), rz.x());
      const double gu = d.head<2>().dot(u);
      const double q = u.dot(W.topLeftCorner<2, 2>() * u);
      const double lambda = phase_c_.z() / (gamma_.z() * tau);
      const double total = lambda * gu * wsum_[e.pa].z();
      const double bound = q > 0 ? std::min(phase_.max_turn, std::abs(0.5 * gu / q)) : 0.0;
      const double scale = std::abs(total) > bound ? bound / std::abs(total) : 1.0;
      range_add_theta(e.pa, -scale * lambda * gu);
      change = std::max(change, std::abs(scale * total));
    }
    Eigen::Vector3d c;
    for (int i = 0; i < 3; ++i) {
      const double tw = wsum_[hi][i] - wsum_[lo - 1][i];
      // The papers' factor l, or (second phase) the common C_i.
      double beta = (phase ? phase_c_[i] * tw : l) * d[i] / (gamma_[i] * tau);
      if (std::abs(beta) > std::abs(r[i])) beta = r[i];
      c[i] = sign * beta / tw;
      change = std::max(change, std::abs(beta));
    }
    range_add(lo, hi, c);
  }
  for (int p = n_ - 1; p >= 0; --p) pose0_[p] = query(p);
  return change;
}

void ChainSgd2D::write_back(PoseGraph& g) const {
  for (int p = 0; p < n_; ++p)
    g.vertex_at(vertex_[chain_[p]]).pose2 = SE2(pose0_[p].x(), pose0_[p].y(), wrap_angle(pose0_[p].z()));
}

}  // namespace slamkit::detail
