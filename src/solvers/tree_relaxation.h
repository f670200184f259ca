// The engine SGD (Olson, Leonard, Teller 2006) and TORO (Grisetti et al. 2007) share: poses
// parameterized along a tree (SGD: the odometry chain, TORO: a spanning tree), and per
// constraint a gradient-like update that spreads its residual over the tree path between its
// two ends, each node's share inversely proportional to its preconditioner M_k.
//
//   2D  parameters are global-frame increments p_k = x_k − x_parent (x, y, θ), so a pose is the
//       sum of the increments from the root. With G = blockdiag(R(θa + θz), 1), the residual is
//       r = G·(−e) (e the g2o error), the global information W = G Ω Gᵀ, and
//       β = clamp(l · α · 2Wr, |r|),  α_i = 1 / (γ_i · iteration),  Δp_k = ±β_i / (M_k,i Σ_path 1/M_i)
//       (+ on the path to the edge's target, − towards its source; M_k = Σ diag W over the edges
//       whose path crosses k, γ = min diag W).
//   3D  parameters are relative motions p_k = x_parent⁻¹ x_k, updated in two steps (TORO 3D):
//       the rotational residual R_a R_z R_bᵀ (an axis-angle ω in the global frame) is spread as
//       rotations Exp(c_k · f_r · ω) with c_k the cumulative weight along the path from a to b, then
//       the translational residual (x_a x_z).t − x_b.t is spread as cumulative translations;
//       f_r = min(1, √l · ω_e / (γ_r · iteration)), f_t = min(1, l · ω_e,t / (γ_t · iteration)).
//   2D, second phase (RelaxerGradientPhase, from iteration `start` on): every constraint takes
//       the same learning rate, λ_i = C_i / (γ_i τ), τ = t0 + t − start, C_i the quantile of
//       c_e,i = l / Σ_path 1/M_k,i, i.e. Δp_k = ±λ_i W r / M_k,i (clamped as above), and the θ
//       increments from the root to a take the coupling step −λ_θ (2 (W r)_xy · u) / M_k,θ,
//       u = ∂r_xy/∂θ_a = perp(R(θa) z_xy), its sum bounded by the 1-D Newton step and max_turn;
//       M_k,θ then also sums uᵀ W_xy u over the constraints whose root-to-a path holds k.
// One update costs O(depth) (the exact pose of the path's top is recomputed from the root);
// an iteration O(Σ_edges (path length + depth)). Internal to the solvers module.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "slamkit/core/pose_graph.h"
#include "slamkit/solvers/relaxer.h"

namespace slamkit::detail {

/// Parent per pose of a breadth-first spanning tree rooted at `root` (−1 at the root).
std::vector<int> bfs_tree(const RelaxerGraph& rg, int root);
/// Parent per pose of the chain in id order, rooted at `root` (the chain runs away from it).
std::vector<int> id_chain(const PoseGraph& g, const RelaxerGraph& rg, int root);
/// The root the tree relaxers hold fixed: the first gauge pose.
int tree_root(const RelaxerGraph& rg);

/// When SGD/TORO's second phase begins: wraps the stop rule to record the best chi2 of every
/// iteration, and gives the phase to use in iteration t (start fixed once the stall is seen).
class GradientPhaseSchedule {
 public:
  explicit GradientPhaseSchedule(const RelaxerGradientPhase& phase) : phase_(phase) {}
  RelaxerStop wrap(const RelaxerStop& stop);
  RelaxerGradientPhase at(int iteration);
  /// "gradient phase from iteration N" once it began (empty before).
  std::string note() const;

 private:
  RelaxerGradientPhase phase_;
  std::vector<double> best_;  // best chi2 up to iteration k (entry 0: the start)
};

class TreeRelaxation {
 public:
  TreeRelaxation(const PoseGraph& g, const RelaxerGraph& rg, std::vector<int> parent);
  /// 2D: the unbiased second phase (default: never).
  void set_gradient_phase(const RelaxerGradientPhase& phase) { phase_ = phase; }
  /// Length of the tree path between the ends of edge e.
  int path_length(int e) const;
  /// One pass over the edges in `order`; returns the max |parameter change|.
  double iterate(int iteration, const std::vector<int>& order);
  /// Writes the poses into the graph's vertex estimates.
  void write_back(PoseGraph& g) const;

 private:
  struct Edge {
    int a, b;
    Eigen::Vector3d z2 = Eigen::Vector3d::Zero();  // 2D measurement (x, y, θ)
    Eigen::Matrix3d info2 = Eigen::Matrix3d::Zero();
    double cz = 1, sz = 0;  // cos, sin of the 2D measurement's θ
    Eigen::Quaterniond zq = Eigen::Quaterniond::Identity();
    Eigen::Vector3d zt = Eigen::Vector3d::Zero();
    double w_rot = 0, w_trans = 0;  // 3D: smallest diagonal entry of the rotation / translation information
  };
  void path(int e, std::vector<int>* a_side, std::vector<int>* b_side, int* top) const;
  double update_2d(const Edge& e, int iteration);
  double update_3d(const Edge& e, int iteration);
  void preconditioner_2d(int iteration);
  bool in_phase(int iteration) const { return phase_.start > 0 && iteration > phase_.start; }
  RelaxerGradientPhase phase_{0};
  Eigen::Vector3d phase_c_ = Eigen::Vector3d::Zero();  // C of the second phase
  // 2D state
  std::vector<Eigen::Vector3d> inc_;  // global increments
  Eigen::Vector3d gamma2_;
  std::vector<Eigen::Vector3d> m2_, minv2_;  // M per node and 1/M
  // 3D state: relative motions to the parent (root: its global pose)
  std::vector<Eigen::Quaterniond> rq_;
  std::vector<Eigen::Vector3d> rt_;
  std::vector<Eigen::Vector2d> m3_;  // (rotation, translation)
  double gamma_rot_ = 0, gamma_trans_ = 0;

  int dim_;
  std::vector<int> parent_, depth_, topo_;
  std::vector<std::size_t> vertex_;
  std::vector<Edge> edges_;
  // scratch
  mutable std::vector<int> sa_, sb_;
  std::vector<Eigen::Quaterniond> pq_;
  std::vector<Eigen::Vector3d> pt_;
};

}  // namespace slamkit::detail
