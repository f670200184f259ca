#include "tree_relaxation.h"
#include "relaxer_math_2d.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>

namespace slamkit::detail {

RelaxerStop GradientPhaseSchedule::wrap(const RelaxerStop& stop) {
  RelaxerStop s = stop;
  s.callback = [this, user = stop.callback](const RelaxerIteration& it) {
    best_.push_back(best_.empty() ? it.chi2 : std::min(best_.back(), it.chi2));
    return !user || user(it);
  };
  return s;
}

RelaxerGradientPhase GradientPhaseSchedule::at(int iteration) {
  if (phase_.start != 0) return phase_;
  const int k = static_cast<int>(best_.size()) - 1;  // the last finished iteration
  if (k == iteration - 1 && k > phase_.window &&
      best_[k] > (1.0 - phase_.stall) * best_[static_cast<std::size_t>(k - phase_.window)])
    phase_.start = k;  // iteration k + 1 is the phase's first
  RelaxerGradientPhase p = phase_;
  if (p.start == 0) p.start = -1;  // not yet
  return p;
}

std::string GradientPhaseSchedule::note() const {
  const int first = phase_.start + 1;
  if (phase_.start <= 0 || first >= static_cast<int>(best_.size())) return "";
  return "gradient phase (common learning rate, full Jacobian) from iteration " + std::to_string(first);
}

int tree_root(const RelaxerGraph& rg) {
  for (std::size_t k = 0; k < rg.gauge.size(); ++k)
    if (rg.gauge[k]) return static_cast<int>(k);
  return 0;
}

std::vector<int> bfs_tree(const RelaxerGraph& rg, int root) {
  const std::size_t n = rg.vertex.size();
  std::vector<std::vector<int>> adj(n);
  for (const auto& [a, b] : rg.ends) {
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  std::vector<int> parent(n, -2);
  parent[root] = -1;
  std::deque<int> q{root};
  while (!q.empty()) {
    const int a = q.front();
    q.pop_front();
    for (int b : adj[a])
      if (parent[b] == -2) parent[b] = a, q.push_back(b);
  }
  return parent;  // connected (make_relaxer_graph checked): every entry is set
}

std::vector<int> id_chain(const PoseGraph& g, const RelaxerGraph& rg, int root) {
  const std::size_t n = rg.vertex.size();
  std::vector<int> by_id(n);
  std::iota(by_id.begin(), by_id.end(), 0);
  std::sort(by_id.begin(), by_id.end(),
            [&](int x, int y) { return g.vertices()[rg.vertex[x]].id < g.vertices()[rg.vertex[y]].id; });
  const auto r = std::find(by_id.begin(), by_id.end(), root) - by_id.begin();
  std::vector<int> parent(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const auto ii = static_cast<std::ptrdiff_t>(i);
    if (ii > r) parent[by_id[i]] = by_id[i - 1];
    if (ii < r) parent[by_id[i]] = by_id[i + 1];
  }
  return parent;
}

TreeRelaxation::TreeRelaxation(const PoseGraph& g, const RelaxerGraph& rg, std::vector<int> parent)
    : dim_(rg.dimension), parent_(std::move(parent)), vertex_(rg.vertex) {
  const std::size_t n = vertex_.size();
  // Parents before children.
  std::vector<std::vector<int>> children(n);
  int root = -1;
  for (std::size_t k = 0; k < n; ++k) {
    if (parent_[k] < 0) root = static_cast<int>(k);
    else children[parent_[k]].push_back(static_cast<int>(k));
  }
  depth_.assign(n, 0);
  topo_ = {root};
  for (std::size_t i = 0; i < topo_.size(); ++i)
    for (int c : children[topo_[i]]) depth_[c] = depth_[topo_[i]] + 1, topo_.push_back(c);

  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    const GraphEdge& ge = g.edges[e];
    Edge x;
    x.a = rg.ends[e].first;
    x.b = rg.ends[e].second;
    if (dim_ == 2) {
      x.z2 = Eigen::Vector3d(ge.pose2.x(), ge.pose2.y(), ge.pose2.theta());
      x.info2 = 0.5 * (ge.information + ge.information.transpose());
      x.cz = std::cos(x.z2.z());
      x.sz = std::sin(x.z2.z());
    } else {
      x.zq = ge.pose3.rotation().quaternion();
      x.zt = ge.pose3.translation();
      const Eigen::VectorXd d = ge.information.diagonal();
      x.w_trans = d.head<3>().minCoeff();
      x.w_rot = d.tail<3>().minCoeff();
    }
    edges_.push_back(x);
  }
  if (dim_ == 2) {
    inc_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const SE2& x = g.vertices()[vertex_[k]].pose2;
      if (parent_[k] < 0) {
        inc_[k] = Eigen::Vector3d(x.x(), x.y(), x.theta());
      } else {
        const SE2& p = g.vertices()[vertex_[parent_[k]]].pose2;
        inc_[k] = Eigen::Vector3d(x.x() - p.x(), x.y() - p.y(), wrap_angle(x.theta() - p.theta()));
      }
    }
    m2_.assign(n, Eigen::Vector3d::Zero());
  } else {
    rq_.resize(n);
    rt_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const SE3& x = g.vertices()[vertex_[k]].pose3;
      if (parent_[k] < 0) {
        rq_[k] = x.rotation().quaternion();
        rt_[k] = x.translation();
      } else {
        const SE3& p = g.vertices()[vertex_[parent_[k]]].pose3;
        const Eigen::Quaterniond pq = p.rotation().quaternion();
        rq_[k] = (pq.conjugate() * x.rotation().quaternion()).normalized();
        rt_[k] = pq.conjugate() * (x.translation() - p.translation());
      }
    }
    // TORO's 3D preconditioner does not depend on the poses: compute it once.
    m3_.assign(n, Eigen::Vector2d::Zero());
    gamma_rot_ = gamma_trans_ = std::numeric_limits<double>::infinity();
    std::vector<int> A, B;
    int top = 0;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      path(static_cast<int>(e), &A, &B, &top);
      gamma_rot_ = std::min(gamma_rot_, edges_[e].w_rot);
      gamma_trans_ = std::min(gamma_trans_, edges_[e].w_trans);
      for (const auto* side : {&A, &B})
        for (int k : *side) m3_[k] += Eigen::Vector2d(edges_[e].w_rot, edges_[e].w_trans);
    }
  }
}

void TreeRelaxation::path(int e, std::vector<int>* A, std::vector<int>* B, int* top) const {
  int a = edges_[e].a, b = edges_[e].b;
  A->clear();
  B->clear();
  while (depth_[a] > depth_[b]) A->push_back(a), a = parent_[a];
  while (depth_[b] > depth_[a]) B->push_back(b), b = parent_[b];
  while (a != b) {
    A->push_back(a), a = parent_[a];
    B->push_back(b), b = parent_[b];
  }
  *top = a;
}

int TreeRelaxation::path_length(int e) const {
  int top = 0;
  path(e, &sa_, &sb_, &top);
  return static_cast<int>(sa_.size() + sb_.size());
}

void TreeRelaxation::preconditioner_2d(int iteration) {
  const std::size_t n = vertex_.size();
  const bool phase = in_phase(iteration);
  std::vector<double> theta(n, 0.0);
  for (int k : topo_) theta[k] = (parent_[k] < 0 ? 0.0 : theta[parent_[k]]) + inc_[k].z();
  std::fill(m2_.begin(), m2_.end(), Eigen::Vector3d::Zero());
  gamma2_.setConstant(std::numeric_limits<double>::infinity());
  int top = 0;
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const Edge& x = edges_[e];
    const double ca = std::cos(theta[x.a]), sa = std::sin(theta[x.a]);
    const Eigen::Matrix3d W = rotate_information(x.info2, ca * x.cz - sa * x.sz, sa * x.cz + ca * x.sz);
    const Eigen::Vector3d w = W.diagonal();
    gamma2_ = gamma2_.cwiseMin(w);
    path(static_cast<int>(e), &sa_, &sb_, &top);
    for (const auto* side : {&sa_, &sb_})
      for (int k : *side) m2_[k] += w;
    if (phase) {  // the coupling's diagonal uᵀ W_xy u on the θ increments from the root to a
      const Eigen::Vector2d rz = rot2(ca, sa) * x.z2.head<2>();
      const Eigen::Vector2d u(-rz.y(), rz.x());
      const double q = u.dot(W.topLeftCorner<2, 2>() * u);
      for (int k = x.a; parent_[k] >= 0; k = parent_[k]) m2_[k].z() += q;
    }
  }
  minv2_.resize(n);
  for (std::size_t k = 0; k < n; ++k) minv2_[k] = m2_[k].cwiseInverse();
  // C moves slowly with the orientations: refreshed every 10 iterations of the phase.
  if (!phase || ((iteration - phase_.start) % 10 != 1 && phase_c_.minCoeff() > 0)) return;
  std::vector<double> c[3];
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    path(static_cast<int>(e), &sa_, &sb_, &top);
    Eigen::Vector3d tw = Eigen::Vector3d::Zero();
    for (const auto* side : {&sa_, &sb_})
      for (int k : *side) tw += minv2_[k];
    for (int i = 0; i < 3; ++i) c[i].push_back(static_cast<double>(sa_.size() + sb_.size()) / tw[i]);
  }
  for (int i = 0; i < 3; ++i) {
    const auto q = c[i].begin() + static_cast<std::ptrdiff_t>(phase_.quantile * static_cast<double>(c[i].size() - 1));
    std::nth_element(c[i].begin(), q, c[i].end());
    phase_c_[i] = *q;
  }
}

double TreeRelaxation::update_2d(const Edge& e, int iteration) {
  int top = 0;
  path(static_cast<int>(&e - edges_.data()), &sa_, &sb_, &top);
  Eigen::Vector3d p_top = Eigen::Vector3d::Zero();
  for (int k = top; k >= 0; k = parent_[k]) p_top += inc_[k];
  Eigen::Vector3d pa = p_top, pb = p_top;
  for (int k : sa_) pa += inc_[k];
  for (int k : sb_) pb += inc_[k];
  const double ca = std::cos(pa.z()), sa = std::sin(pa.z());
  const Eigen::Vector2d rz = rot2(ca, sa) * e.z2.head<2>();  // R(θa) z_xy
  Eigen::Vector3d r;
  r.head<2>() = pa.head<2>() + rz - pb.head<2>();
  r.z() = wrap_angle(pa.z() + e.z2.z() - pb.z());
  const Eigen::Matrix3d W = rotate_information(e.info2, ca * e.cz - sa * e.sz, sa * e.cz + ca * e.sz);
  const Eigen::Vector3d d = 2.0 * W * r;
  const double l = static_cast<double>(sa_.size() + sb_.size());
  const bool phase = in_phase(iteration);
  const double tau = phase ? phase_.t0 + (iteration - phase_.start) : iteration;
  Eigen::Vector3d beta, tw = Eigen::Vector3d::Zero();
  for (const auto* side : {&sa_, &sb_})
    for (int k : *side) tw += minv2_[k];
  for (int i = 0; i < 3; ++i) {
    // The papers' factor l, or (second phase) the common C_i: Σ_path λ W r / M_k = C_i tw_i d_i / (γ_i τ).
    beta[i] = (phase ? phase_c_[i] * tw[i] : l) * d[i] / (gamma2_[i] * tau);
    if (std::abs(beta[i]) > std::abs(r[i])) beta[i] = r[i];
  }
  double change = 0.0;
  if (phase) {  // coupling: ∂r_xy/∂θ_a = u, a step on the θ increments from the root to a
    const Eigen::Vector2d u(-rz.y(), rz.x());
    const double gu = d.head<2>().dot(u);  // ∂(rᵀWr)/∂θ_a through r_xy
    const double q = u.dot(W.topLeftCorner<2, 2>() * u);
    const double lambda = phase_c_.z() / (gamma2_.z() * tau);
    double total = 0.0;
    for (int k = e.a; parent_[k] >= 0; k = parent_[k]) total += lambda * gu * minv2_[k].z();
    const double bound = q > 0 ? std::min(phase_.max_turn, std::abs(0.5 * gu / q)) : 0.0;
    const double scale = std::abs(total) > bound ? bound / std::abs(total) : 1.0;
    for (int k = e.a; parent_[k] >= 0; k = parent_[k]) inc_[k].z() -= scale * lambda * gu * minv2_[k].z();
    change = std::abs(scale * total);
  }
  const Eigen::Vector3d share = beta.cwiseQuotient(tw);
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    for (int k : side == 0 ? sa_ : sb_) {
      const Eigen::Vector3d delta = sign * share.cwiseProduct(minv2_[k]);
      inc_[k] += delta;
      change = std::max(change, delta.cwiseAbs().maxCoeff());
    }
  }
  return change;
}

double TreeRelaxation::update_3d(const Edge& e, int iteration) {
  int top = 0;
  path(static_cast<int>(&e - edges_.data()), &sa_, &sb_, &top);
  const int ti = static_cast<int>(sa_.size());
  const int l = ti + static_cast<int>(sb_.size());
  // Path P[0] = a … P[ti] = top … P[l] = b, with global poses (pq_, pt_).
  std::vector<int>& P = sa_;
  P.push_back(top);
  for (auto it = sb_.rbegin(); it != sb_.rend(); ++it) P.push_back(*it);
  pq_.resize(P.size());
  pt_.resize(P.size());
  // Exact global pose of the top: compose from the root down.
  Eigen::Quaterniond tq = Eigen::Quaterniond::Identity();
  Eigen::Vector3d tt = Eigen::Vector3d::Zero();
  sb_.clear();
  for (int k = top; k >= 0; k = parent_[k]) sb_.push_back(k);
  for (auto it = sb_.rbegin(); it != sb_.rend(); ++it) {
    tt = tt + tq * rt_[*it];
    tq = tq * rq_[*it];
  }
  auto chain_from_top = [&] {
    pq_[ti] = tq;
    pt_[ti] = tt;
    for (int i = ti - 1; i >= 0; --i) pt_[i] = pt_[i + 1] + pq_[i + 1] * rt_[P[i]], pq_[i] = pq_[i + 1] * rq_[P[i]];
    for (int i = ti + 1; i <= l; ++i) pt_[i] = pt_[i - 1] + pq_[i - 1] * rt_[P[i]], pq_[i] = pq_[i - 1] * rq_[P[i]];
  };
  chain_from_top();
  auto weight = [&](int i, int c) { return 1.0 / m3_[P[i]][c]; };
  double tot_r = 0, tot_t = 0;
  for (int i = 0; i <= l; ++i)
    if (i != ti) tot_r += weight(i, 0), tot_t += weight(i, 1);

  // Rotation: spread ω (global frame) so that a turns by 0 and b by the whole f_r ω.
  const Eigen::AngleAxisd res((pq_[0] * e.zq) * pq_[l].conjugate());
  const double f_r = std::min(1.0, std::sqrt(double(l)) * e.w_rot / (gamma_rot_ * iteration));
  double cw = 0;
  for (int i = 1; i <= l; ++i) {
    cw += (i <= ti ? weight(i - 1, 0) : weight(i, 0)) / tot_r;
    pq_[i] = Eigen::Quaterniond(Eigen::AngleAxisd(res.angle() * cw * f_r, res.axis())) * pq_[i];
  }
  for (int i = 0; i < ti; ++i) rq_[P[i]] = (pq_[i + 1].conjugate() * pq_[i]).normalized();
  for (int i = ti + 1; i <= l; ++i) rq_[P[i]] = (pq_[i - 1].conjugate() * pq_[i]).normalized();
  chain_from_top();

  // Translation: spread the residual as cumulative shifts, −towards a, + towards b.
  const double f_t = std::min(1.0, double(l) * e.w_trans / (gamma_trans_ * iteration));
  const Eigen::Vector3d dt = f_t * (pt_[0] + pq_[0] * e.zt - pt_[l]);
  double cum = 0;
  for (int i = ti - 1; i >= 0; --i) cum -= weight(i, 1) / tot_t, pt_[i] += cum * dt;
  cum = 0;
  for (int i = ti + 1; i <= l; ++i) cum += weight(i, 1) / tot_t, pt_[i] += cum * dt;
  for (int i = 0; i < ti; ++i) rt_[P[i]] = pq_[i + 1].conjugate() * (pt_[i] - pt_[i + 1]);
  for (int i = ti + 1; i <= l; ++i) rt_[P[i]] = pq_[i - 1].conjugate() * (pt_[i] - pt_[i - 1]);
  return std::max(std::abs(res.angle() * f_r), dt.norm());
}

double TreeRelaxation::iterate(int iteration, const std::vector<int>& order) {
  if (dim_ == 2) preconditioner_2d(iteration);
  double change = 0.0;
  for (int e : order) {
    const Edge& x = edges_[e];
    const double c = dim_ == 3 ? update_3d(x, iteration) : update_2d(x, iteration);
    change = std::max(change, c);
  }
  return change;
}

void TreeRelaxation::write_back(PoseGraph& g) const {
  const std::size_t n = vertex_.size();
  if (dim_ == 2) {
    std::vector<Eigen::Vector3d> pose(n);
    for (int k : topo_) pose[k] = (parent_[k] < 0 ? Eigen::Vector3d::Zero() : pose[parent_[k]]) + inc_[k];
    for (std::size_t k = 0; k < n; ++k) g.vertex_at(vertex_[k]).pose2 = SE2(pose[k].x(), pose[k].y(), wrap_angle(pose[k].z()));
    return;
  }
  std::vector<Eigen::Quaterniond> q(n);
  std::vector<Eigen::Vector3d> t(n);
  for (int k : topo_) {
    const int p = parent_[k];
    if (p < 0) {
      q[k] = rq_[k];
      t[k] = rt_[k];
    } else {
      t[k] = t[p] + q[p] * rt_[k];
      q[k] = (q[p] * rq_[k]).normalized();
    }
  }
  for (std::size_t k = 0; k < n; ++k) g.vertex_at(vertex_[k]).pose3 = SE3(q[k], t[k]);
}

}  // namespace slamkit::detail
