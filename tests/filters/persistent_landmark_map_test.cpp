// The copy-on-write landmark tree of FastSLAM: lookups, balance after many inserts, sharing of
// untouched subtrees between copies, no mutation of other copies, node counts after resampling.
#include "slamkit/filters/persistent_landmark_map.h"

#include <gtest/gtest.h>

#include <random>

namespace slamkit {
namespace {

LandmarkGaussian at(double x) {
  LandmarkGaussian g;
  g.mean = Eigen::Vector2d(x, -x);
  return g;
}

TEST(PersistentLandmarkMap, InsertFindAndBalance) {
  PersistentLandmarkMap m;
  EXPECT_EQ(m.find(3), nullptr);
  std::mt19937 rng(7);
  std::vector<int> keys(1000);
  for (int i = 0; i < 1000; ++i) keys[i] = i;
  std::shuffle(keys.begin(), keys.end(), rng);
  for (int k : keys) m.set(k, at(k));
  for (int k = 0; k < 1000; k += 10) m.set(k, at(2 * k));  // replacements do not grow the map
  EXPECT_EQ(m.size(), 1000u);
  ASSERT_TRUE(m.valid());
  EXPECT_LE(m.height(), 15);  // AVL: h < 1.44 log2(n + 2) ≈ 14.4
  for (int k = 0; k < 1000; ++k) {
    ASSERT_NE(m.find(k), nullptr);
    EXPECT_DOUBLE_EQ(m.find(k)->mean.x(), k % 10 == 0 ? 2.0 * k : k);
  }
  EXPECT_EQ(m.find(1000), nullptr);
  PersistentLandmarkMap ascending;  // the worst order for an unbalanced tree
  for (int k = 0; k < 4096; ++k) ascending.set(k, at(k));
  EXPECT_TRUE(ascending.valid());
  EXPECT_LE(ascending.height(), 13);
  int previous = -1;
  ascending.for_each([&](int id, const LandmarkGaussian&) {
    EXPECT_GT(id, previous);
    previous = id;
  });
}

TEST(PersistentLandmarkMap, CopiesShareAndNeverMutateEachOther) {
  PersistentLandmarkMap a;
  for (int k = 0; k < 1024; ++k) a.set(k, at(k));
  PersistentLandmarkMap b = a;
  EXPECT_EQ(a.root(), b.root());
  EXPECT_EQ(PersistentLandmarkMap::distinct_nodes({&a, &b}), 1024u);
  b.set(500, at(-1));
  // Only the root-to-key path is new.
  const std::size_t extra = PersistentLandmarkMap::distinct_nodes({&a, &b}) - 1024u;
  EXPECT_GE(extra, 1u);
  EXPECT_LE(extra, static_cast<std::size_t>(b.height()));
  EXPECT_DOUBLE_EQ(a.find(500)->mean.x(), 500);
  EXPECT_DOUBLE_EQ(b.find(500)->mean.x(), -1);
  b.set(5000, at(5));  // an insert in b does not appear in a
  EXPECT_EQ(a.find(5000), nullptr);
  EXPECT_EQ(a.size(), 1024u);
  EXPECT_EQ(b.size(), 1025u);
  EXPECT_TRUE(a.valid() && b.valid());
}

TEST(PersistentLandmarkMap, ResamplingCopiesShareNodes) {
  // 100 "particles" from one map, each updates 3 landmarks, then a resampling keeps 10 of them
  // 10 times each: the node count is O(n + M · 3 log n), not O(M n).
  PersistentLandmarkMap base;
  const int n = 2000;
  for (int k = 0; k < n; ++k) base.set(k, at(k));
  std::vector<PersistentLandmarkMap> particles(100, base);
  for (int p = 0; p < 100; ++p)
    for (int j = 0; j < 3; ++j) particles[p].set((p * 37 + j * 11) % n, at(p));
  std::vector<PersistentLandmarkMap> resampled;
  for (int p = 0; p < 100; ++p) resampled.push_back(particles[(p / 10) * 10]);
  std::vector<const PersistentLandmarkMap*> all;
  for (const auto& m : resampled) all.push_back(&m);
  const std::size_t nodes = PersistentLandmarkMap::distinct_nodes(all);
  EXPECT_GE(nodes, static_cast<std::size_t>(n));
  EXPECT_LE(nodes, static_cast<std::size_t>(n + 10 * 3 * base.height()));
  for (const auto& m : resampled) EXPECT_EQ(m.size(), static_cast<std::size_t>(n));
  EXPECT_DOUBLE_EQ(resampled[15].find((10 * 37) % n)->mean.x(), 10);
  EXPECT_DOUBLE_EQ(base.find((10 * 37) % n)->mean.x(), (10 * 37) % n);
}

}  // namespace
}  // namespace slamkit
