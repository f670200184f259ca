// SEIF: equal to the EIF when nothing is sparsified; bounded active set and fill-in, no NaN,
// symmetric covariances and a usable estimate with either passive-landmark rule.
#include "slamkit/filters/seif.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include "filter_test_util.h"
#include "slamkit/filters/eif.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

using testing::small_world;

TEST(Seif, WithActiveBoundAtLeastTheLandmarkCountEqualsTheEif) {
  auto w = small_world(12, 400);
  w.filter.initial_sigma << 0.1, 0.1, 0.01;
  w.filter.pose_noise_floor.setConstant(1e-3);
  w.filter.active_landmarks = 12;
  SeifOptions so;
  so.recovery_sweeps = 2000;  // converged mean recovery: the linearization points agree
  so.recovery_extra = 100;
  const LandmarkSimRun run = simulate_landmark_run(w.landmarks, w.waypoints, w.sim, 11);
  Eif eif(w.filter);
  Seif seif(w.filter, so);
  double worst_pose = 0, worst_cov = 0;
  for (const auto& s : run.steps) {
    const Control u{s.v, s.steer, w.sim.dt};
    eif.predict(u);
    seif.predict(u);
    if (s.observed) {
      eif.update(s.observations);
      seif.update(s.observations);
      ASSERT_EQ(seif.landmarks().size(), eif.landmarks().size());
      Eigen::Vector3d d = seif.pose() - eif.pose();
      d(2) = wrap_angle(d(2));
      worst_pose = std::max(worst_pose, d.cwiseAbs().maxCoeff());
      worst_cov = std::max(worst_cov, (seif.pose_covariance() - eif.pose_covariance()).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_GE(seif.landmarks().size(), 5u);
  EXPECT_LT(worst_pose, 1e-8);
  EXPECT_LT(worst_cov, 1e-9);
  const auto a = seif.landmarks(), b = eif.landmarks();
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_LT((a[k].mean - b[k].mean).norm(), 1e-8);
    EXPECT_LT((a[k].covariance - b[k].covariance).cwiseAbs().maxCoeff(), 1e-9);
  }
}

void run_sparse(SparsificationRule rule, EntropyRuleOptions::NewLandmarkScore new_score) {
  auto w = small_world(300, 2000, 6, 150.0);  // a 940 m loop, 150 m of it driven
  w.filter.active_landmarks = 4;
  SeifOptions so;
  so.rule = rule;
  so.entropy.new_landmarks = new_score;
  const LandmarkSimRun run = simulate_landmark_run(w.landmarks, w.waypoints, w.sim, 2);
  Seif seif(w.filter, so);
  double sq = 0;
  int n = 0;
  testing::run_filter(&seif, run, w.sim, [&](std::size_t k) {
    if (!run.steps[k].observed) return;
    ASSERT_LE(seif.active_count(), 4);
    ASSERT_TRUE(seif.pose().allFinite());
    if (k % 200 == 7) {
      const Eigen::Matrix3d P = seif.pose_covariance();
      ASSERT_TRUE(P.allFinite());
      EXPECT_LT((P - P.transpose()).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_GT(P.ldlt().vectorD().minCoeff(), 0.0);
    }
    sq += (seif.pose().head<2>() - run.steps[k].true_pose.head<2>()).squaredNorm();
    ++n;
  });
  EXPECT_GT(seif.size(), 30u);
  // Fill-in stays local: landmarks link only to landmarks that were active with them, i.e.
  // that were seen within 30 m of the vehicle while it drove a few metres.
  int links = 0;
  for (const auto& l : seif.landmarks())
    for (int other : seif.linked_landmarks(l.id)) {
      EXPECT_LT((w.landmarks[l.id] - w.landmarks[other]).norm(), 2 * w.sim.max_range + 30.0);
      ++links;
    }
  EXPECT_GT(links, 0);
  EXPECT_LT(std::sqrt(sq / n), 5.0) << seif.name();
  for (const auto& l : seif.landmarks()) {
    ASSERT_TRUE(l.mean.allFinite());
    EXPECT_LT((l.covariance - l.covariance.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(Seif, StandardRuleKeepsTheActiveBound) {
  run_sparse(SparsificationRule::kStandard, EntropyRuleOptions::NewLandmarkScore::kPoseEntropy);
}

TEST(Seif, EntropyRuleKeepsTheActiveBoundInEveryConfiguration) {
  for (auto s : {EntropyRuleOptions::NewLandmarkScore::kPoseEntropy, EntropyRuleOptions::NewLandmarkScore::kCurrentTwice,
                 EntropyRuleOptions::NewLandmarkScore::kKeepActive})
    run_sparse(SparsificationRule::kEntropy, s);
}

TEST(Seif, EntropyRuleMakesTheUnobservedLandmarkPassive) {
  // Active set {0, 1} at t; at t+1 only landmark 1 and a new landmark 2 are seen, bound A = 2:
  // landmark 0 (unobserved: maximal H(x_{t+1} | m)) is the one to go (P2's case 4).
  auto w = small_world(1, 1);
  w.filter.active_landmarks = 2;
  SeifOptions so;
  so.rule = SparsificationRule::kEntropy;
  Seif seif(w.filter, so);
  seif.update({RangeBearing{0, 10.0, 0.3}, RangeBearing{1, 12.0, -0.4}});
  seif.predict(Control{3.0, 0.0, 0.025});
  seif.update({RangeBearing{1, 12.0, -0.41}, RangeBearing{2, 8.0, 1.0}});
  ASSERT_EQ(seif.active_count(), 2);
  EXPECT_FALSE(seif.is_active(0));
  EXPECT_TRUE(seif.is_active(1));
  EXPECT_TRUE(seif.is_active(2));
  // Landmark 0 lost its pose link: its marginal mean/covariance remain, the pose is still fine.
  const auto map = seif.landmarks();
  ASSERT_EQ(map.size(), 3u);
  EXPECT_TRUE(seif.pose_covariance().allFinite());
  // The standard rule, by contrast, drops the least recently observed too — also landmark 0.
  so.rule = SparsificationRule::kStandard;
  Seif standard(w.filter, so);
  standard.update({RangeBearing{0, 10.0, 0.3}, RangeBearing{1, 12.0, -0.4}});
  standard.predict(Control{3.0, 0.0, 0.025});
  standard.update({RangeBearing{1, 12.0, -0.41}, RangeBearing{2, 8.0, 1.0}});
  EXPECT_EQ(standard.active_count(), 2);
  EXPECT_FALSE(standard.is_active(0));
}

}  // namespace
}  // namespace slamkit
