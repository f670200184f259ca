// Association: evo's nearest-stamp rule, unequal rates, gaps, offsets, ties, index matching,
// and a randomized comparison with a brute-force implementation of the rule.
#include "slamkit/eval/association.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

Trajectory at_stamps(const std::vector<double>& t) {
  Trajectory traj;
  for (double s : t) traj.push_back(s, SE3());
  return traj;
}

/// evo's rule written the slow, obvious way: iterate the shorter (est on equal length),
/// argmin over the longer with its stamps shifted, first minimum on ties.
Association brute_force(const Trajectory& est, const Trajectory& ref, double max_diff, double offset) {
  const bool est_longer = est.size() > ref.size();
  const Trajectory& s = est_longer ? ref : est;
  const Trajectory& l = est_longer ? est : ref;
  const double shift = est_longer ? offset : -offset;
  Association a;
  for (std::size_t i = 0; i < s.size(); ++i) {
    std::size_t best = 0;
    double best_d = std::abs((l[0].stamp + shift) - s[i].stamp);
    for (std::size_t j = 1; j < l.size(); ++j) {
      const double d = std::abs((l[j].stamp + shift) - s[i].stamp);
      if (d < best_d) best = j, best_d = d;
    }
    if (best_d <= max_diff) {
      (est_longer ? a.ref_ids : a.est_ids).push_back(i);
      (est_longer ? a.est_ids : a.ref_ids).push_back(best);
    }
  }
  return a;
}

TEST(Association, UnequalRates) {
  // Reference at 100 Hz, estimate at 30 Hz with 2 ms jitter: every estimate pose matches the
  // reference pose nearest to it.
  std::vector<double> ref, est;
  for (int k = 0; k < 1000; ++k) ref.push_back(100.0 + 0.01 * k);
  for (int k = 0; k < 300; ++k) est.push_back(100.0 + k / 30.0 + ((k % 3) - 1) * 0.002);
  const Association a = associate(at_stamps(est), at_stamps(ref), {});
  ASSERT_EQ(a.size(), 300u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a.est_ids[k], k);
    EXPECT_EQ(a.ref_ids[k], static_cast<std::size_t>(std::lround((est[k] - 100.0) / 0.01)));
  }
  EXPECT_FALSE(a.by_index);
}

TEST(Association, GapsDropUnmatchedPoses) {
  // Reference 20 Hz with a 1 s hole in [2, 3) s; estimate 10 Hz throughout.
  std::vector<double> ref, est;
  for (int k = 0; k < 100; ++k)
    if (k < 40 || k >= 60) ref.push_back(0.05 * k);
  for (int k = 0; k < 50; ++k) est.push_back(0.1 * k + 0.003);
  const Association a = associate(at_stamps(est), at_stamps(ref), {});
  // Estimate stamps 2.003 … 2.903 (k = 20 … 29) have no reference within 10 ms.
  EXPECT_EQ(a.size(), 40u);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_TRUE(a.est_ids[k] < 20 || a.est_ids[k] >= 30);
}

TEST(Association, OffsetIsAddedToTheEstimateStamps) {
  std::vector<double> ref, est;
  for (int k = 0; k < 50; ++k) ref.push_back(10.0 + 0.1 * k), est.push_back(9.95 + 0.1 * k);
  AssociationOptions opt;
  EXPECT_THROW(associate(at_stamps(est), at_stamps(ref), opt), Error);  // 50 ms apart
  opt.offset = 0.05;
  const Association a = associate(at_stamps(est), at_stamps(ref), opt);
  EXPECT_EQ(a.size(), 50u);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a.est_ids[k], a.ref_ids[k]);
  // The same when the estimate is the longer trajectory (the shift moves to the other side).
  est.push_back(9.95 + 0.1 * 50);
  const Association b = associate(at_stamps(est), at_stamps(ref), opt);
  EXPECT_EQ(b.size(), 50u);
}

TEST(Association, ShorterTrajectoryIsIteratedAndTiesTakeTheFirst) {
  // Reference shorter: each reference stamp takes its nearest estimate stamp, so one estimate
  // sample may serve two reference samples (as in evo). Stamps are exact binary fractions.
  const Trajectory est = at_stamps({0.0, 0.25, 0.5, 1.0, 1.25, 1.5});
  const Trajectory ref = at_stamps({0.25, 0.3125, 1.125});
  AssociationOptions opt;
  opt.max_diff = 0.2;
  const Association a = associate(est, ref, opt);
  EXPECT_EQ(a.est_ids, (std::vector<std::size_t>{1, 1, 3}));  // 1.125: tie 1.0 / 1.25 → the first
  EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{0, 1, 2}));
  // Estimate shorter (or equal): the estimate is iterated.
  const Association b = associate(at_stamps({0.5, 0.625}), at_stamps({0.0, 0.5, 1.0}), opt);
  EXPECT_EQ(b.est_ids, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(b.ref_ids, (std::vector<std::size_t>{1, 1}));
}

TEST(Association, DuplicatedStampsMatchTheFirstOccurrence) {
  const Association a = associate(at_stamps({1.0, 2.0}), at_stamps({0.0, 1.0, 1.0, 1.0, 2.0, 2.0, 3.0}), {});
  EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{1, 4}));
}

TEST(Association, MatchesBruteForceOnRandomStamps) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> step(0.0, 0.05), u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> a, b;
    double t = 1e9 * u(rng);
    const int na = 1 + static_cast<int>(u(rng) * 80), nb = 1 + static_cast<int>(u(rng) * 80);
    for (int k = 0; k < na; ++k) a.push_back(t += (u(rng) < 0.1 ? 0.0 : step(rng)));  // with duplicates
    t = a.front() - 0.1 + 0.2 * u(rng);
    for (int k = 0; k < nb; ++k) b.push_back(t += step(rng) * (u(rng) < 0.05 ? 20.0 : 1.0));  // with gaps
    const double max_diff = 0.02 * u(rng), offset = 0.02 * (u(rng) - 0.5);
    const Trajectory est = at_stamps(a), ref = at_stamps(b);
    const Association expected = brute_force(est, ref, max_diff, offset);
    if (expected.size() == 0) {
      EXPECT_THROW(associate(est, ref, {max_diff, offset}), Error);
      continue;
    }
    const Association got = associate(est, ref, {max_diff, offset});
    EXPECT_EQ(got.est_ids, expected.est_ids) << "trial " << trial;
    EXPECT_EQ(got.ref_ids, expected.ref_ids) << "trial " << trial;
  }
}

TEST(Association, ByIndexWithoutTimestamps) {
  Trajectory est = at_stamps({0, 1, 2}), ref = at_stamps({5, 6, 7});
  est.set_has_timestamps(false);
  const Association a = associate(est, ref, {});
  EXPECT_TRUE(a.by_index);
  EXPECT_EQ(a.est_ids, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{0, 1, 2}));
  ref.push_back(8, SE3());
  EXPECT_THROW(associate(est, ref, {}), Error);
  EXPECT_THROW(associate(Trajectory(), ref, {}), Error);
  EXPECT_THROW(associate(at_stamps({1}), ref, {-1.0, 0.0}), Error);
}

}  // namespace
}  // namespace slamkit
