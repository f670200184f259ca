#include "sgd_chain_2d.h"

#include <cmath>
#include <algorithm>
#include <limits>

namespace slamkit::detail {
namespace {
double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }
Eigen::Matrix2d rot2(double th) {
  Eigen::Matrix2d R;
  R << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
  return R;
}
}  // namespace

ChainSgd2D::ChainSgd2D(const PoseGraph& g, const RelaxerGraph& rg, std::vector<int> chain)
    : chain_(std::move(chain)), vertex_(rg.vertex), n_(static_cast<int>(chain_.size())) {
  std::vector<int> position(n_);
  for (int p = 0; p < n_; ++p) position[chain_[p]] = p;
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const GraphEdge& ge = g.edges[e];
    edges_.push_back({position[rg.ends[e].first], position[rg.ends[e].second],
                      Eigen::Vector3d(ge.pose2.x(), ge.pose2.y(), ge.pose2.theta()),
                      0.5 * (ge.information + ge.information.transpose())});
  }
  // Unwrapped orientations along the chain, so that increments stay small.
  pose0_.resize(n_);
  for (int p = 0; p < n_; ++p) {
    const SE2& x = g.vertices()[vertex_[chain_[p]]].pose2;
    pose0_[p] = Eigen::Vector3d(x.x(), x.y(), x.theta());
    if (p > 0) pose0_[p].z() = pose0_[p - 1].z() + wrap(x.theta() - pose0_[p - 1].z());
  }
  for (int i = 0; i < 3; ++i) {
    w_[i].assign(n_, 0.0);
    wsum_[i].assign(n_, 0.0);
    s1_[i].assign(n_ + 2, 0.0);
    s2_[i].assign(n_ + 2, 0.0);
  }
}

double ChainSgd2D::query(int i, int p) const {
  double a = 0, b = 0;
  for (int k = p + 1; k > 0; k -= k & -k) a += s1_[i][k], b += s2_[i][k];
  return pose0_[p][i] + wsum_[i][p] * a + b;
}

void ChainSgd2D::range_add(int i, int lo, int hi, double c) {
  const double before = lo > 0 ? wsum_[i][lo - 1] : 0.0;
  for (int k = lo + 1; k <= n_ + 1; k += k & -k) s1_[i][k] += c, s2_[i][k] -= c * before;
  for (int k = hi + 2; k <= n_ + 1; k += k & -k) s1_[i][k] -= c, s2_[i][k] += c * wsum_[i][hi];
}

double ChainSgd2D::iterate(int iteration, const std::vector<int>& order) {
  // Preconditioner: M_k = Σ diag W over the edges whose range covers k (a difference array).
  // Second phase: + uᵀ W_xy u on the θ increments 1..a (the coupling's diagonal).
  const bool phase = phase_.start > 0 && iteration > phase_.start;
  std::vector<Eigen::Vector3d> m(n_ + 1, Eigen::Vector3d::Zero());
  gamma_.setConstant(std::numeric_limits<double>::infinity());
  for (const Edge& e : edges_) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
    G.topLeftCorner<2, 2>() = rot2(pose0_[e.pa].z() + e.z.z());
    const Eigen::Matrix3d W = G * e.info * G.transpose();
    const Eigen::Vector3d w = W.diagonal();
    gamma_ = gamma_.cwiseMin(w);
    const int lo = std::min(e.pa, e.pb) + 1, hi = std::max(e.pa, e.pb);
    m[lo] += w;
    m[hi + 1] -= w;
    if (phase && e.pa > 0) {
      const Eigen::Vector2d rz = rot2(pose0_[e.pa].z()) * e.z.head<2>();
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
      w_[i][p] = p > 0 && run[i] > 0 ? 1.0 / run[i] : 0.0;
      wsum_[i][p] = (p > 0 ? wsum_[i][p - 1] : 0.0) + w_[i][p];
    }
  }
  for (int i = 0; i < 3; ++i) {
    std::fill(s1_[i].begin(), s1_[i].end(), 0.0);
    std::fill(s2_[i].begin(), s2_[i].end(), 0.0);
  }
  if (phase) {  // C: the quantile of the path-length factors l / Σ_path 1/M
    std::vector<double> c(edges_.size());
    for (int i = 0; i < 3; ++i) {
      for (std::size_t k = 0; k < edges_.size(); ++k) {
        const int lo = std::min(edges_[k].pa, edges_[k].pb) + 1, hi = std::max(edges_[k].pa, edges_[k].pb);
        c[k] = (hi - lo + 1) / (wsum_[i][hi] - wsum_[i][lo - 1]);
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
    const Eigen::Vector3d pa(query(0, e.pa), query(1, e.pa), query(2, e.pa));
    const Eigen::Vector3d pb(query(0, e.pb), query(1, e.pb), query(2, e.pb));
    const double th12 = pa.z() + e.z.z();
    Eigen::Vector3d r;
    r.head<2>() = pa.head<2>() + rot2(pa.z()) * e.z.head<2>() - pb.head<2>();
    r.z() = wrap(th12 - pb.z());
    Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
    G.topLeftCorner<2, 2>() = rot2(th12);
    const Eigen::Matrix3d W = G * e.info * G.transpose();
    const Eigen::Vector3d d = 2.0 * W * r;
    const int lo = std::min(e.pa, e.pb) + 1, hi = std::max(e.pa, e.pb);
    const double l = hi - lo + 1;
    // Increments between a and b move b (a before b on the chain) or a (b before a).
    const double sign = e.pa < e.pb ? 1.0 : -1.0;
    if (phase && e.pa > 0) {  // coupling: ∂r_xy/∂θ_a = u, a step on the θ increments 1..a
      const Eigen::Vector2d rz = rot2(pa.z()) * e.z.head<2>();
      const Eigen::Vector2d u(-rz.y(), rz.x());
      const double gu = d.head<2>().dot(u);
      const double q = u.dot(W.topLeftCorner<2, 2>() * u);
      const double lambda = phase_c_.z() / (gamma_.z() * tau);
      const double total = lambda * gu * wsum_[2][e.pa];
      const double bound = q > 0 ? std::min(phase_.max_turn, std::abs(0.5 * gu / q)) : 0.0;
      const double scale = std::abs(total) > bound ? bound / std::abs(total) : 1.0;
      range_add(2, 1, e.pa, -scale * lambda * gu);
      change = std::max(change, std::abs(scale * total));
    }
    for (int i = 0; i < 3; ++i) {
      const double tw = wsum_[i][hi] - wsum_[i][lo - 1];
      // The papers' factor l, or (second phase) the common C_i.
      double beta = (phase ? phase_c_[i] * tw : l) * d[i] / (gamma_[i] * tau);
      if (std::abs(beta) > std::abs(r[i])) beta = r[i];
      const double c = sign * beta / tw;
      range_add(i, lo, hi, c);
      change = std::max(change, std::abs(beta));
    }
  }
  for (int p = n_ - 1; p >= 0; --p)
    pose0_[p] = Eigen::Vector3d(query(0, p), query(1, p), query(2, p));
  return change;
}

void ChainSgd2D::write_back(PoseGraph& g) const {
  for (int p = 0; p < n_; ++p)
    g.vertex_at(vertex_[chain_[p]]).pose2 = SE2(pose0_[p].x(), pose0_[p].y(), wrap(pose0_[p].z()));
}

}  // namespace slamkit::detail
