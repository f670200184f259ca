#include "slamkit/sim/pose_graph_generator.h"
#include "slamkit/sim/calibration_generator.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit {
namespace {

TEST(PoseGraphGenerator, DeterministicConnectedAndTrueOnGroundTruth) {
  for (const char* world : {"manhattan", "sphere"}) {
    PoseGraphSimOptions o;
    o.world = world;
    o.num_poses = 500;
    PoseGraph truth, again;
    const PoseGraph g = generate_pose_graph(o, &truth);
    const PoseGraph h = generate_pose_graph(o, &again);
    EXPECT_EQ(g.edges.size(), h.edges.size());
    EXPECT_EQ(total_chi2(g), total_chi2(h));
    EXPECT_EQ(count_connected_components(g), 1u);
    EXPECT_GT(g.edges.size(), g.vertices().size());  // has loop closures
    // χ² of the ground truth is the noise itself: ≈ dof = Σ error dims (within 6σ).
    double dof = 0;
    for (const auto& e : truth.edges) dof += error_dim(e.kind);
    EXPECT_NEAR(total_chi2(truth), dof, 6.0 * std::sqrt(2.0 * dof)) << world;
    EXPECT_GT(total_chi2(g), total_chi2(truth));  // odometry drift
  }
}

using Pairs = std::multiset<std::pair<std::int64_t, std::int64_t>>;

// The graphs have the size and connectivity their options specify: every closure the spec asks
// for and no other, checked against a direct scan over all pose pairs of the ground truth (the
// generators find closures through grids; this is the quadratic definition they must match).
TEST(PoseGraphGenerator, SizeAndConnectivityAsSpecified) {
  {  // manhattan: a chain, plus closures j > i + 2 within loop_radius, each kept with loop_probability
    PoseGraphSimOptions o;
    o.num_poses = 3000;
    PoseGraph truth;
    const PoseGraph g = generate_pose_graph(o, &truth);
    ASSERT_EQ(g.vertices().size(), 3000u);
    std::size_t candidates = 0;
    for (int j = 0; j < o.num_poses; ++j)
      for (int i = 0; i + 2 < j; ++i)
        candidates += (truth.vertices()[i].pose2.translation() - truth.vertices()[j].pose2.translation()).norm() < o.loop_radius;
    std::size_t closures = 0;
    for (std::size_t k = 0; k < g.edges.size(); ++k) {
      const GraphEdge& e = g.edges[k];
      if (k + 1 < g.vertices().size()) {  // the odometry chain comes first
        EXPECT_EQ(e.to, e.from + 1);
        continue;
      }
      ++closures;
      EXPECT_GT(e.to, e.from + 2);
      EXPECT_LT((truth.vertex(e.from).pose2.translation() - truth.vertex(e.to).pose2.translation()).norm(), o.loop_radius);
    }
    ASSERT_GT(candidates, 1000u);
    const double p = o.loop_probability, sd = std::sqrt(candidates * p * (1 - p));
    EXPECT_NEAR(static_cast<double>(closures), p * candidates, 6 * sd);  // a binomial draw per candidate
    EXPECT_EQ(count_connected_components(g), 1u);
  }
  {  // sphere: chain + same azimuth on the ring below + the next azimuth on the ring below
    PoseGraphSimOptions o;
    o.world = "sphere", o.rings = 7, o.poses_per_ring = 11;
    const PoseGraph g = generate_pose_graph(o);
    ASSERT_EQ(g.vertices().size(), 77u);
    Pairs expected, got;
    for (int i = 0; i + 1 < 77; ++i) expected.insert({i, i + 1});
    for (int r = 1; r < 7; ++r)
      for (int k = 0; k < 11; ++k) {
        expected.insert({(r - 1) * 11 + k, r * 11 + k});
        if (k + 1 < 11) expected.insert({(r - 1) * 11 + k + 1, r * 11 + k});
      }
    for (const GraphEdge& e : g.edges) got.insert({e.from, e.to});
    EXPECT_EQ(got, expected);
  }
  for (const char* spec : {"sim:calib2d?laps=6", "sim:calib2d?laps=3&path=line", "sim:calib3d?laps=4"}) {
    // calib2d: odometry + scan per step, and scan closures (j even, j > i + 60) near in position
    // (loop_radius) and heading (0.5 rad); calib3d: steps, 12-step windows, one lap back.
    CalibrationSimOptions o;
    ASSERT_TRUE(parse_calibration_sim_spec(spec, &o));
    PoseGraph truth;
    const PoseGraph g = generate_calibration_problem(o, nullptr, &truth);
    const int n = static_cast<int>(g.vertices().size());
    Pairs expected, got;
    for (const GraphEdge& e : g.edges) got.insert({e.from, e.to});
    if (o.world == "calib2d") {
      ASSERT_EQ(n, o.laps * 172 + 1);
      for (int i = 0; i + 1 < n; ++i) expected.insert({i, i + 1}), expected.insert({i, i + 1});
      for (int j = 0; j < n; j += 2)
        for (int i = 0; i + 60 < j; ++i) {
          const SE2 d = truth.vertices()[i].pose2.between(truth.vertices()[j].pose2);
          if (d.translation().norm() < o.loop_radius && std::abs(d.theta()) < 0.5) expected.insert({i, j});
        }
      if (o.path == "figure") EXPECT_GT(expected.size(), 2u * (n - 1) + 100) << spec;  // it has closures
    } else {
      ASSERT_EQ(n, o.laps * 120);
      for (int i = 0; i + 1 < n; ++i) expected.insert({i, i + 1}), expected.insert({i, i + 1});
      for (int i = 0; i + 12 < n; i += 3) expected.insert({i, i + 12});
      for (int j = 120; j < n; j += 2) expected.insert({j - 120, j});
    }
    EXPECT_EQ(got, expected) << spec;
    EXPECT_EQ(count_connected_components(g), 1u) << spec;
  }
}

TEST(PoseGraphGenerator, ParsesSpecs) {
  PoseGraphSimOptions o;
  EXPECT_FALSE(parse_sim_spec("graph.g2o", &o));
  ASSERT_TRUE(parse_sim_spec("sim:sphere?seed=7&rings=5", &o));
  EXPECT_EQ(o.world, "sphere");
  EXPECT_EQ(o.seed, 7u);
  EXPECT_EQ(o.rings, 5);
  EXPECT_THROW(parse_sim_spec("sim:cube", &o), InputError);
  EXPECT_THROW(parse_sim_spec("sim:sphere?seed=x", &o), InputError);
  EXPECT_THROW(parse_sim_spec("sim:sphere?colour=1", &o), InputError);
}

// Fuzz findings: values must be whole integers in range, parameters must belong to the world,
// and what parses prints (to_sim_spec) as a spec that parses to the same options.
TEST(PoseGraphGenerator, SpecsAreStrictAndRoundTrip) {
  PoseGraphSimOptions o;
  for (const char* bad : {"sim:manhattan?poses=12abc", "sim:manhattan?poses=", "sim:manhattan?poses=1",
                          "sim:manhattan?seed=-1", "sim:manhattan?seed=4294967296", "sim:manhattan?rings=41",
                          "sim:sphere?poses=10", "sim:sphere?rings=5000&per_ring=5000", "sim:manhattan?poses=99999999999"}) {
    try {
      parse_sim_spec(bad, &o);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), bad);
    }
  }
  for (const char* good : {"sim:manhattan", "sim:sphere", "sim:manhattan?poses=50&seed=4294967295",
                           "sim:sphere?per_ring=7&seed=0&rings=3"}) {
    ASSERT_TRUE(parse_sim_spec(good, &o)) << good;
    PoseGraphSimOptions again;
    ASSERT_TRUE(parse_sim_spec(to_sim_spec(o), &again)) << to_sim_spec(o);
    EXPECT_EQ(again.world, o.world);
    EXPECT_EQ(again.seed, o.seed);
    EXPECT_EQ(again.num_poses, o.num_poses);
    EXPECT_EQ(again.rings, o.rings);
    EXPECT_EQ(again.poses_per_ring, o.poses_per_ring);
  }
}

}  // namespace
}  // namespace slamkit
