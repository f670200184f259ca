// RPE pair selection for each delta unit (frames, metres, degrees, radians, seconds),
// consecutive and all pairs, against hand-computed index lists.
#include "slamkit/eval/pair_selection.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

using Pairs = IndexPairs;

/// n poses along x with the given step lengths, rotating about z by `yaw_step` [rad] per pose,
/// at 10 Hz.
Trajectory line(const std::vector<double>& steps, double yaw_step = 0.0) {
  Trajectory t;
  double x = 0.0;
  for (std::size_t k = 0; k <= steps.size(); ++k) {
    if (k > 0) x += steps[k - 1];
    t.push_back(0.1 * static_cast<double>(k), SE3(SO3::from_rpy(0, 0, yaw_step * static_cast<double>(k)), Eigen::Vector3d(x, 0, 0)));
  }
  return t;
}

TEST(PairSelection, Frames) {
  const Trajectory t = line(std::vector<double>(9, 1.0));  // 10 poses
  EXPECT_EQ(select_pairs(t, 3, DeltaUnit::kFrames, false), (Pairs{{0, 3}, {3, 6}, {6, 9}}));
  EXPECT_EQ(select_pairs(t, 4, DeltaUnit::kFrames, true), (Pairs{{0, 4}, {1, 5}, {2, 6}, {3, 7}, {4, 8}, {5, 9}}));
  EXPECT_EQ(select_pairs(t, 1, DeltaUnit::kFrames, false).size(), 9u);
  EXPECT_THROW(select_pairs(t, 2.5, DeltaUnit::kFrames, false), Error);
  EXPECT_THROW(select_pairs(t, 10, DeltaUnit::kFrames, false), Error);  // no pair
}

TEST(PairSelection, MetresConsecutiveFollowsEvo) {
  // Unit steps: the path from pose 0 reaches 2.5 m at pose 3 (the chain starts there, not at
  // pose 0), then restarts: 6, 9.
  const Trajectory t = line(std::vector<double>(10, 1.0));
  EXPECT_EQ(select_pairs(t, 2.5, DeltaUnit::kMeters, false), (Pairs{{3, 6}, {6, 9}}));
  EXPECT_EQ(select_pairs(t, 1.0, DeltaUnit::kMeters, false).front(), (std::pair<std::size_t, std::size_t>{1, 2}));
  // Uneven steps: path 0.4 0.8 ... accumulate 0.5, 1.4 (≥1 at pose 2), restart: 0.2+0.9 (pose 4).
  const Trajectory u = line({0.5, 0.9, 0.2, 0.9, 0.05, 0.05, 1.0});
  EXPECT_EQ(select_pairs(u, 1.0, DeltaUnit::kMeters, false), (Pairs{{2, 4}, {4, 7}}));
}

TEST(PairSelection, MetresAllPairsPickTheClosestPathLength) {
  const Trajectory t = line(std::vector<double>(8, 1.0));  // path lengths 0..8
  EXPECT_EQ(select_pairs(t, 3.0, DeltaUnit::kMeters, true),
            (Pairs{{0, 3}, {1, 4}, {2, 5}, {3, 6}, {4, 7}, {5, 8}}));
  // 3.4 m: the nearest path length is 3 (off by 0.4 > tol 0.34) → none; with tol 0.2 (rel) → all.
  EXPECT_THROW(select_pairs(t, 3.4, DeltaUnit::kMeters, true), Error);
  EXPECT_EQ(select_pairs(t, 3.4, DeltaUnit::kMeters, true, 0.2).size(), 6u);
  // Standing still (zero steps) makes plateaus: the FIRST pose of the best plateau is taken.
  const Trajectory s = line({1.0, 0.0, 0.0, 1.0, 1.0});  // path 0 1 1 1 2 3
  EXPECT_EQ(select_pairs(s, 1.0, DeltaUnit::kMeters, true),
            (Pairs{{0, 1}, {1, 4}, {2, 4}, {3, 4}, {4, 5}}));
}

TEST(PairSelection, DegreesAndRadians) {
  const double deg = kPi / 180.0;
  const Trajectory t = line(std::vector<double>(9, 0.1), 10.0 * deg);  // 10° per pose
  EXPECT_EQ(select_pairs(t, 25.0, DeltaUnit::kDegrees, false), (Pairs{{0, 3}, {3, 6}, {6, 9}}));
  EXPECT_EQ(select_pairs(t, 25.0 * deg, DeltaUnit::kRadians, false), (Pairs{{0, 3}, {3, 6}, {6, 9}}));
  EXPECT_EQ(select_pairs(t, 30.0, DeltaUnit::kDegrees, true),
            (Pairs{{0, 3}, {1, 4}, {2, 5}, {3, 6}, {4, 7}, {5, 8}, {6, 9}}));
  // The direct angle, not the accumulated one: a back-and-forth rotation.
  Trajectory w;
  for (int k = 0; k < 5; ++k) w.push_back(k, SE3(SO3::from_rpy(0, 0, (k % 2) * 20.0 * deg), Eigen::Vector3d(k, 0, 0)));
  EXPECT_EQ(select_pairs(w, 20.0, DeltaUnit::kDegrees, true), (Pairs{{0, 1}, {0, 3}, {1, 2}, {1, 4}, {2, 3}, {3, 4}}));
  EXPECT_EQ(select_pairs(w, 39.0, DeltaUnit::kDegrees, false), (Pairs{{0, 2}, {2, 4}}));  // 20 + 20 accumulated
  EXPECT_THROW(select_pairs(t, 181.0, DeltaUnit::kDegrees, false), Error);
}

TEST(PairSelection, Seconds) {
  const Trajectory t = line(std::vector<double>(20, 1.0));  // 10 Hz, 21 poses
  EXPECT_EQ(select_pairs(t, 0.35, DeltaUnit::kSeconds, false),
            (Pairs{{0, 4}, {4, 8}, {8, 12}, {12, 16}, {16, 20}}));
  const Pairs all = select_pairs(t, 0.5, DeltaUnit::kSeconds, true);
  ASSERT_EQ(all.size(), 16u);
  for (const auto& [i, j] : all) EXPECT_EQ(j, i + 5);
  Trajectory kitti = t;
  kitti.set_has_timestamps(false);
  EXPECT_THROW(select_pairs(kitti, 1.0, DeltaUnit::kSeconds, false), Error);
}

TEST(PairSelection, InvalidDeltaAndUnitNames) {
  const Trajectory t = line(std::vector<double>(5, 1.0));
  EXPECT_THROW(select_pairs(t, 0.0, DeltaUnit::kMeters, false), Error);
  EXPECT_THROW(select_pairs(t, -1.0, DeltaUnit::kFrames, false), Error);
  EXPECT_THROW(select_pairs(t, 1.0, DeltaUnit::kMeters, false, -0.1), Error);
  for (DeltaUnit u : {DeltaUnit::kFrames, DeltaUnit::kMeters, DeltaUnit::kDegrees, DeltaUnit::kRadians, DeltaUnit::kSeconds}) {
    EXPECT_EQ(parse_delta_unit(to_string(u)), u);
    EXPECT_EQ(parse_delta_unit(long_name(u)), u);
  }
  EXPECT_THROW(parse_delta_unit("km"), InputError);
}

}  // namespace
}  // namespace slamkit
