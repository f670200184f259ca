// Monte-Carlo consistency evaluation: thread-independent results, the χ² bounds, the summary
// statistics on known inputs, and the plots.
#include "slamkit/eval/filter_consistency.h"

#include <gtest/gtest.h>

#include "slamkit/core/error.h"
#include "slamkit/eval/filter_plots.h"
#include "slamkit/filters/filter_factory.h"

namespace slamkit {
namespace {

struct World {
  std::vector<Eigen::Vector2d> lm, wp;
  LandmarkSimOptions sim;
  LandmarkFilterOptions filter;
};

World world() {
  World w;
  generate_landmark_world(30, 2, &w.lm, &w.wp);
  w.sim.max_steps = 800;
  w.filter.motion = std::make_shared<BicycleModel>(w.sim.wheelbase, w.sim.sigma_v, w.sim.sigma_steer);
  w.filter.sensor = RangeBearingModel(w.sim.sigma_range, w.sim.sigma_bearing);
  return w;
}

TEST(FilterConsistency, MonteCarloDoesNotDependOnThreadsAndIsConsistentForEkf) {
  const World w = world();
  auto make = [&] { return make_landmark_filter("ekf", w.filter); };
  MonteCarloOptions o;
  o.runs = 6;
  o.threads = 1;
  int calls = 0;
  o.progress = [&](int done, int total) {
    ++calls;
    EXPECT_LE(done, total);
  };
  const auto one = run_monte_carlo(make, w.lm, w.wp, w.sim, o);
  o.threads = 2;
  const auto two = run_monte_carlo(make, w.lm, w.wp, w.sim, o);
  EXPECT_EQ(calls, 12);
  ASSERT_EQ(one.size(), 6u);
  for (std::size_t r = 0; r < one.size(); ++r) {
    EXPECT_EQ(one[r].seed, r + 1);
    ASSERT_EQ(one[r].nees, two[r].nees);
  }
  const ConsistencySummary s = summarize_consistency(one);
  EXPECT_EQ(s.time.size(), 100u);  // 800 control steps, an observation every 8
  EXPECT_TRUE(s.finite);
  EXPECT_GT(s.anees_mean, 1.5);
  EXPECT_LT(s.anees_mean, 5.0);
  EXPECT_GT(s.fraction_in_bounds, 0.6);
  EXPECT_NEAR(s.anis, 1.0, 0.3);
  EXPECT_LT(s.rmse_position_total, 2.0);
  EXPECT_TRUE(std::isfinite(s.map_nees));
  EXPECT_EQ(s.landmarks, int(one[0].final_map.size()));
  const std::string svg = filter_dashboard("ekf", one[0], s, w.lm).str();
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("ANEES"), std::string::npos);
}

TEST(FilterConsistency, SummaryOfKnownRunsAndBounds) {
  std::vector<FilterRunResult> runs(30);
  for (auto& r : runs) {
    r.time = {0.2, 0.4};
    r.truth = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    r.estimate = {Eigen::Vector3d(3, 4, 0), Eigen::Vector3d(0, 0, 0.1)};
    r.covariance = {Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Identity()};
    r.nees = {3.0, 10.0};
    r.step_ms = {1.0, 3.0};
  }
  const ConsistencySummary s = summarize_consistency(runs);
  EXPECT_NEAR(s.anees_lo, 2.188, 5e-4);
  EXPECT_NEAR(s.anees_hi, 3.938, 5e-4);
  EXPECT_DOUBLE_EQ(s.fraction_in_bounds, 0.5);
  EXPECT_DOUBLE_EQ(s.anees_mean, 6.5);
  EXPECT_NEAR(s.rmse_position_total, std::sqrt(25.0 / 2), 1e-12);
  EXPECT_NEAR(s.rmse_heading_total, std::sqrt(0.01 / 2), 1e-12);
  EXPECT_DOUBLE_EQ(s.time_per_step_mean_ms, 2.0);
  EXPECT_DOUBLE_EQ(s.time_per_step_max_ms, 3.0);
  runs[3].nees.pop_back();
  EXPECT_THROW(summarize_consistency(runs), InputError);
  EXPECT_THROW(make_landmark_filter("fastslam2", LandmarkFilterOptions{}), InputError);
  EXPECT_THROW(make_landmark_filter("ukf", LandmarkFilterOptions{}), InputError);
}

}  // namespace
}  // namespace slamkit
