#include "slamkit/sim/landmark_sim.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/io/landmark_map_io.h"

namespace slamkit {
namespace {

TEST(LandmarkSim, SameSeedSameDrawsAndObservationsWithinRange) {
  std::vector<Eigen::Vector2d> lm, wp;
  generate_landmark_world(50, 3, &lm, &wp);
  LandmarkSimOptions o;
  o.max_steps = 2000;
  LandmarkSimRun a = simulate_landmark_run(lm, wp, o, 7), b = simulate_landmark_run(lm, wp, o, 7);
  ASSERT_EQ(a.steps.size(), 2000u);
  int observed = 0;
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    EXPECT_EQ(a.steps[k].v, b.steps[k].v);
    EXPECT_EQ(a.steps[k].observations.size(), b.steps[k].observations.size());
    EXPECT_EQ(a.steps[k].observed, (k + 1) % 8 == 0);
    for (const auto& z : a.steps[k].observations) {
      EXPECT_LT(z.range, o.max_range + 1.0);
      ++observed;
    }
  }
  EXPECT_GT(observed, 100);
  // The vehicle follows the route: it reaches the first waypoint region.
  double closest = 1e9;
  for (const auto& s : a.steps) closest = std::min(closest, (s.true_pose.head<2>() - wp[0]).norm());
  EXPECT_LT(closest, 1.5);
}

TEST(LandmarkSim, SurveyScanSeesEveryLandmarkBeyondRange) {
  std::vector<Eigen::Vector2d> lm, wp;
  generate_landmark_world(400, 2, &lm, &wp);
  LandmarkSimOptions o;
  const Eigen::Vector3d pose(0, 0, 0.3);
  const auto a = survey_scan(lm, pose, o, 9), b = survey_scan(lm, pose, o, 9);
  int far = 0, expected = 0;
  for (const auto& p : lm) expected += (p - pose.head<2>()).norm() >= o.min_range;
  ASSERT_EQ(int(a.size()), expected);
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].range, b[i].range);  // seeded
    const double r = (lm[a[i].id] - pose.head<2>()).norm();
    far += r > o.max_range;
    worst = std::max(worst, std::abs(a[i].range - r) / o.sigma_range);
  }
  EXPECT_GT(far, 100);    // beyond the 30 m sensor range
  EXPECT_LT(worst, 6.0);  // noise of the sensor's σ
  EXPECT_THROW(survey_scan(lm, Eigen::Vector3d(NAN, 0, 0), o, 1), InputError);
}

TEST(LandmarkMapIo, ReadsAndRejectsMalformedWithLine) {
  std::istringstream good("#type columns rows\nlm 2 2\n1 2\n3 4\n\nwp 2 1\n5 6\n");
  LandmarkMap m = read_landmark_map(good, "m.txt");
  ASSERT_EQ(m.landmarks.size(), 2u);
  EXPECT_EQ(m.waypoints[0].y(), 6.0);
  std::istringstream bad("lm 2 2\n1 2\n3 x\nwp 2 1\n5 6\n");
  try {
    read_landmark_map(bad, "m.txt");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "y");
  }
  std::istringstream short_section("lm 2 3\n1 2\nwp 2 1\n5 6\n");
  EXPECT_THROW(read_landmark_map(short_section, "m.txt"), InputError);
  std::istringstream no_wp("lm 2 1\n1 2\n");
  EXPECT_THROW(read_landmark_map(no_wp, "m.txt"), InputError);
}

}  // namespace
}  // namespace slamkit
