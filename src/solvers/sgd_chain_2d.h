// SGD in 2D on the odometry chain with O(log N) updates (Olson, Leonard, Teller 2006 keep
// the cumulative sums of the increments in a tree for the same reason). Positions 0..n−1 along
// the chain, the root (gauge) at 0; a constraint's path is the range (lo, hi] of positions,
// and TORO/SGD's update adds c_i · w_k,i (w = 1/M) to every increment in it. So each
// coordinate keeps two Fenwick trees: with W(p) = Σ_{k≤p} w_k, a range add (l, r, c) adds
// c·(W(min(p, r)) − W(l − 1)) to the pose at p ≥ l, i.e. W(p)·S1(p) + S2(p) with S1 += c at l,
// −c at r+1 and S2 += −c·W(l−1) at l, +c·W(r) at r+1. Poses are materialized once per
// iteration (the preconditioner M changes with the orientations). The second phase
// (RelaxerGradientPhase) adds the coupling step on the θ increments 1..a, a prefix range add
// in the same trees. Internal.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/core/pose_graph.h"
#include "slamkit/solvers/relaxer.h"

namespace slamkit::detail {

class ChainSgd2D {
 public:
  /// chain: the pose index at each position (chain[0] the root).
  ChainSgd2D(const PoseGraph& g, const RelaxerGraph& rg, std::vector<int> chain);
  void set_gradient_phase(const RelaxerGradientPhase& phase) { phase_ = phase; }
  double iterate(int iteration, const std::vector<int>& order);
  void write_back(PoseGraph& g) const;

 private:
  /// The pose at position p (all three coordinates in one tree walk).
  Eigen::Vector3d query(int p) const;
  /// Adds c_i · w_k,i to coordinate i of the increments at positions lo..hi (inclusive).
  void range_add(int lo, int hi, const Eigen::Vector3d& c);
  void range_add_theta(int hi, double c);  // θ only, positions 1..hi
  struct Edge {
    int pa, pb;
    Eigen::Vector3d z;
    double cz, sz;  // cos, sin of z_θ
    Eigen::Matrix3d info;
  };
  struct Node {  // one Fenwick node of the three coordinates' trees
    Eigen::Vector3d s1 = Eigen::Vector3d::Zero(), s2 = Eigen::Vector3d::Zero();
  };
  std::vector<int> chain_;
  std::vector<std::size_t> vertex_;
  std::vector<Edge> edges_;
  int n_;
  std::vector<Eigen::Vector3d> pose0_;  // poses at the start of the iteration
  std::vector<Eigen::Vector3d> wsum_;  // prefix sums of w = 1/M per position (wsum[p] = Σ_{k≤p} w_k)
  std::vector<Node> tree_;             // Fenwick trees S1, S2 of the three coordinates, 1-based
  Eigen::Vector3d gamma_;
  RelaxerGradientPhase phase_{0};
  Eigen::Vector3d phase_c_ = Eigen::Vector3d::Zero();
};

}  // namespace slamkit::detail
