// The landmark map of one FastSLAM particle: a persistent (immutable-node) AVL tree keyed by
// landmark id. Copying a map copies one pointer; set() copies only the O(log n) nodes on the
// path from the root to the key (path copying), so particles that share a history share all
// untouched subtrees, and changing one particle's map never changes another's.
// Invariants: keys strictly increase in order; |height(left) − height(right)| ≤ 1 at every
// node; a node, once published, is never modified.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace slamkit {

/// One landmark EKF: mean and 2×2 covariance.
struct LandmarkGaussian {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
};

class PersistentLandmarkMap {
 public:
  struct Node;
  using NodePtr = std::shared_ptr<const Node>;
  struct Node {
    int key;
    LandmarkGaussian value;
    int height;
    NodePtr left, right;
  };

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  /// The landmark with this id, or nullptr. O(log n).
  const LandmarkGaussian* find(int id) const;
  /// Inserts or replaces the landmark `id` in this map only. O(log n) new nodes.
  void set(int id, const LandmarkGaussian& value);
  /// Every landmark in increasing id order.
  void for_each(const std::function<void(int, const LandmarkGaussian&)>& f) const;
  /// Height of the tree (0 when empty), for the balance tests.
  int height() const;
  /// Checks the invariants (order, balance, stored heights); for tests.
  bool valid() const;
  /// Number of distinct nodes reachable from all the maps (shared nodes counted once).
  static std::size_t distinct_nodes(const std::vector<const PersistentLandmarkMap*>& maps);
  const Node* root() const { return root_.get(); }

 private:
  NodePtr root_;
  std::size_t size_ = 0;
};

}  // namespace slamkit
