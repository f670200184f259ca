// EKF-SLAM and the EIF: algebraic equality, consistency (NEES inside χ² bounds), symmetric
// covariances, no NaN, and the information-form building blocks.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "filter_test_util.h"
#include "slamkit/core/error.h"
#include "slamkit/filters/chi_square.h"
#include "slamkit/filters/ekf_slam.h"
#include "slamkit/filters/eif.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

using testing::run_filter;
using testing::small_world;

TEST(ChiSquare, KnownQuantilesAndAneesBounds) {
  EXPECT_NEAR(chi2_quantile(0.99, 2), -2 * std::log(0.01), 1e-9);
  EXPECT_NEAR(chi2_quantile(0.95, 1), 3.841458820694124, 1e-9);
  // Two-sided 95% ANEES bounds for N = 30 runs, n = 3: [2.188, 3.938].
  EXPECT_NEAR(chi2_quantile(0.025, 90) / 30, 2.188, 5e-4);
  EXPECT_NEAR(chi2_quantile(0.975, 90) / 30, 3.938, 5e-4);
  EXPECT_NEAR(chi2_cdf(chi2_quantile(0.3, 7), 7), 0.3, 1e-12);
}

TEST(EkfSlam, EqualsEifToOneInABillion) {
  auto w = small_world(12, 400);
  // A well-conditioned problem: Ω₀ = P₀⁻¹ and W = Q̃⁻¹ of moderate size (with the default
  // 1e-4 rad floor, W ≈ 1e8 in the direction F_u cannot reach and the two forms drift apart
  // by round-off, 4e-8 m over 400 steps).
  w.filter.initial_sigma << 0.1, 0.1, 0.01;
  w.filter.pose_noise_floor.setConstant(1e-3);
  const LandmarkSimRun run = simulate_landmark_run(w.landmarks, w.waypoints, w.sim, 11);
  EkfSlam ekf(w.filter);
  Eif eif(w.filter);
  double worst_mean = 0, worst_cov = 0;
  for (std::size_t k = 0; k < run.steps.size(); ++k) {
    const auto& s = run.steps[k];
    const Control u{s.v, s.steer, w.sim.dt};
    ekf.predict(u);
    eif.predict(u);
    if (s.observed) {
      ekf.update(s.observations);
      eif.update(s.observations);
    }
    ASSERT_EQ(ekf.mean().size(), eif.mean().size());
    Eigen::VectorXd d = ekf.mean() - eif.mean();
    d(2) = wrap_angle(d(2));
    worst_mean = std::max(worst_mean, d.cwiseAbs().maxCoeff());
    worst_cov = std::max(worst_cov, (ekf.covariance() - eif.covariance()).cwiseAbs().maxCoeff());
  }
  EXPECT_GE(ekf.landmarks().size(), 5u);
  EXPECT_LT(worst_mean, 1e-9);
  EXPECT_LT(worst_cov, 1e-9);
}

// The capacity hint only changes where P lives: preallocated storage and storage grown as the
// map fills give bit-identical estimates.
TEST(EkfSlam, CapacityHintGivesIdenticalEstimates) {
  auto w = small_world(12, 400);
  const LandmarkSimRun run = simulate_landmark_run(w.landmarks, w.waypoints, w.sim, 5);
  LandmarkFilterOptions hinted = w.filter;
  hinted.expected_landmarks = 3;  // smaller than the map: storage still has to grow
  EkfSlam grown(w.filter), reserved(hinted);
  for (const auto& s : run.steps) {
    const Control u{s.v, s.steer, w.sim.dt};
    grown.predict(u);
    reserved.predict(u);
    if (s.observed) grown.update(s.observations), reserved.update(s.observations);
  }
  ASSERT_GT(grown.landmarks().size(), 3u);
  EXPECT_EQ(grown.mean(), reserved.mean());
  EXPECT_EQ(Eigen::MatrixXd(grown.covariance()), Eigen::MatrixXd(reserved.covariance()));
  hinted.expected_landmarks = -1;
  EXPECT_THROW(EkfSlam bad(hinted), InputError);
}

TEST(EkfSlam, NeesInsideChiSquareBoundsSymmetricNoNan) {
  // 20 runs (seeds 1..20) over 1500 control steps; ANEES of the pose at every observation step
  // must lie within the two-sided 99% bounds of χ²(20·3)/20 in at least 90% of the steps.
  auto w = small_world(35, 1500);
  const int runs = 20;
  std::vector<double> sum;
  for (int seed = 1; seed <= runs; ++seed) {
    const LandmarkSimRun run = simulate_landmark_run(w.landmarks, w.waypoints, w.sim, seed);
    EkfSlam ekf(w.filter);
    std::size_t obs = 0;
    run_filter(&ekf, run, w.sim, [&](std::size_t k) {
      if (!run.steps[k].observed) return;
      Eigen::Vector3d e = ekf.pose() - run.steps[k].true_pose;
      e(2) = wrap_angle(e(2));
      const Eigen::Matrix3d P = ekf.pose_covariance();
      ASSERT_TRUE(ekf.mean().allFinite());
      ASSERT_LT((ekf.covariance() - ekf.covariance().transpose()).cwiseAbs().maxCoeff(), 1e-12);
      const double nees = e.dot(P.ldlt().solve(e));
      if (sum.size() <= obs) sum.push_back(0);
      sum[obs++] += nees;
    });
  }
  const double lo = chi2_quantile(0.005, 3.0 * runs) / runs, hi = chi2_quantile(0.995, 3.0 * runs) / runs;
  int inside = 0;
  double mean = 0;
  for (double s : sum) {
    inside += (s / runs >= lo && s / runs <= hi);
    mean += s / runs / sum.size();
  }
  EXPECT_GE(inside, 0.9 * sum.size()) << "ANEES over time mean " << mean << " bounds [" << lo << ", " << hi << "]";
  EXPECT_NEAR(mean, 3.0, 0.6);
}

TEST(EkfSlam, RejectsBadInputWithNamedField) {
  auto w = small_world(5, 10);
  EkfSlam ekf(w.filter);
  EXPECT_THROW(ekf.predict(Control{std::nan(""), 0, 0.025}), InputError);
  EXPECT_THROW(ekf.update({RangeBearing{0, -1.0, 0}}), InputError);
  EXPECT_THROW(ekf.update({RangeBearing{-1, 5.0, 0}}), InputError);  // known association without id
  LandmarkFilterOptions bad = w.filter;
  bad.motion.reset();
  EXPECT_THROW(EkfSlam{bad}, InputError);
}

TEST(Eif, NewLandmarkFactorMatchesEkfAugmentation) {
  // One observation from a known pose: the EIF's landmark marginal equals G_x P Gxᵀ + G_z R G_zᵀ.
  auto w = small_world(1, 1);
  EkfSlam ekf(w.filter);
  Eif eif(w.filter);
  const std::vector<RangeBearing> z = {RangeBearing{0, 12.0, 0.7}};
  ekf.update(z);
  eif.update(z);
  ASSERT_EQ(eif.landmarks().size(), 1u);
  EXPECT_LT((ekf.landmarks()[0].mean - eif.landmarks()[0].mean).norm(), 1e-12);
  EXPECT_LT((ekf.covariance() - eif.covariance()).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace slamkit
