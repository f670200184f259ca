#include "slamkit/filters/persistent_landmark_map.h"

#include <algorithm>
#include <unordered_set>

namespace slamkit {
namespace {

using Node = PersistentLandmarkMap::Node;
using NodePtr = PersistentLandmarkMap::NodePtr;

int height_of(const NodePtr& n) { return n ? n->height : 0; }

NodePtr make(int key, const LandmarkGaussian& value, NodePtr left, NodePtr right) {
  const int h = 1 + std::max(height_of(left), height_of(right));
  return std::make_shared<const Node>(Node{key, value, h, std::move(left), std::move(right)});
}

// Rebuilds a node from fresh children, restoring |balance| ≤ 1 by one or two rotations (the
// children differ in height by at most 2 after one insertion below).
NodePtr balance(int key, const LandmarkGaussian& value, NodePtr l, NodePtr r) {
  const int hl = height_of(l), hr = height_of(r);
  if (hl > hr + 1) {
    if (height_of(l->left) >= height_of(l->right))  // single right rotation
      return make(l->key, l->value, l->left, make(key, value, l->right, std::move(r)));
    const Node& lr = *l->right;  // left-right double rotation
    return make(lr.key, lr.value, make(l->key, l->value, l->left, lr.left), make(key, value, lr.right, std::move(r)));
  }
  if (hr > hl + 1) {
    if (height_of(r->right) >= height_of(r->left))
      return make(r->key, r->value, make(key, value, std::move(l), r->left), r->right);
    const Node& rl = *r->left;
    return make(rl.key, rl.value, make(key, value, std::move(l), rl.left), make(r->key, r->value, rl.right, r->right));
  }
  return make(key, value, std::move(l), std::move(r));
}

NodePtr insert(const NodePtr& n, int key, const LandmarkGaussian& value, bool* added) {
  if (!n) {
    *added = true;
    return make(key, value, nullptr, nullptr);
  }
  if (key < n->key) return balance(n->key, n->value, insert(n->left, key, value, added), n->right);
  if (key > n->key) return balance(n->key, n->value, n->left, insert(n->right, key, value, added));
  return std::make_shared<const Node>(Node{key, value, n->height, n->left, n->right});  // replace: same shape
}

bool check(const Node* n, const int* lo, const int* hi, int* h) {
  if (!n) {
    *h = 0;
    return true;
  }
  if ((lo && n->key <= *lo) || (hi && n->key >= *hi)) return false;
  int hl = 0, hr = 0;
  if (!check(n->left.get(), lo, &n->key, &hl) || !check(n->right.get(), &n->key, hi, &hr)) return false;
  *h = 1 + std::max(hl, hr);
  return std::abs(hl - hr) <= 1 && n->height == *h;
}

void visit(const Node* n, const std::function<void(int, const LandmarkGaussian&)>& f) {
  if (!n) return;
  visit(n->left.get(), f);
  f(n->key, n->value);
  visit(n->right.get(), f);
}

}  // namespace

const LandmarkGaussian* PersistentLandmarkMap::find(int id) const {
  const Node* n = root_.get();
  while (n) {
    if (id < n->key)
      n = n->left.get();
    else if (id > n->key)
      n = n->right.get();
    else
      return &n->value;
  }
  return nullptr;
}

void PersistentLandmarkMap::set(int id, const LandmarkGaussian& value) {
  bool added = false;
  root_ = insert(root_, id, value, &added);
  if (added) ++size_;
}

void PersistentLandmarkMap::for_each(const std::function<void(int, const LandmarkGaussian&)>& f) const {
  visit(root_.get(), f);
}

int PersistentLandmarkMap::height() const { return height_of(root_); }

bool PersistentLandmarkMap::valid() const {
  int h = 0;
  std::size_t count = 0;
  for_each([&](int, const LandmarkGaussian&) { ++count; });
  return check(root_.get(), nullptr, nullptr, &h) && count == size_;
}

std::size_t PersistentLandmarkMap::distinct_nodes(const std::vector<const PersistentLandmarkMap*>& maps) {
  std::unordered_set<const Node*> seen;
  std::vector<const Node*> stack;
  for (const PersistentLandmarkMap* m : maps)
    if (m->root_) stack.push_back(m->root_.get());
  while (!stack.empty()) {
    const Node* n = stack.back();
    stack.pop_back();
    if (!seen.insert(n).second) continue;  // a shared subtree is walked once
    if (n->left) stack.push_back(n->left.get());
    if (n->right) stack.push_back(n->right.get());
  }
  return seen.size();
}

}  // namespace slamkit
