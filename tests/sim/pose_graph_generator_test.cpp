#include "slamkit/sim/pose_graph_generator.h"

#include <gtest/gtest.h>

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
