// sim:ba: deterministic for a seed, the requested sizes, every point seen by 2+ cameras in
// front of them and inside the image, a perturbed start, and strict spec parsing.
#include <gtest/gtest.h>

#include "slamkit/core/error.h"
#include "slamkit/sim/ba_generator.h"

namespace slamkit {
namespace {

TEST(BaGenerator, SizesVisibilityAndDeterminism) {
  BaSimOptions o;
  o.cameras = 30, o.points = 2000, o.seed = 4;
  BalProblem truth;
  const BalProblem p = generate_ba_problem(o, &truth);
  ASSERT_EQ(p.num_cameras(), 30);
  ASSERT_EQ(p.num_points(), 2000);
  std::vector<int> seen(p.num_points(), 0);
  for (const BalObservation& ob : p.observations) {
    ASSERT_GE(ob.camera, 0);
    ASSERT_LT(ob.camera, 30);
    ++seen[ob.point];
    double pz = 0.0;
    const Eigen::Vector2d u = bal_project(truth.cameras[ob.camera], truth.points[ob.point], &pz);
    EXPECT_LT(pz, 0.0);  // in front of the camera
    EXPECT_LT(std::abs(u.x()), 500.0);
    EXPECT_LT((u - ob.pixel).norm(), 8.0);  // pixel noise σ = 1
  }
  for (int s : seen) EXPECT_GE(s, 2);
  const double per_point = static_cast<double>(p.num_observations()) / p.num_points();
  EXPECT_GT(per_point, 2.5);
  EXPECT_LT(per_point, 8.0);
  // The start is perturbed, the truth is near the optimum.
  EXPECT_GT(bal_cost(p), 10.0 * bal_cost(truth));
  EXPECT_NEAR(bal_cost(truth), 0.5 * 2.0 * p.num_observations(), 0.1 * p.num_observations());
  const BalProblem q = generate_ba_problem(o);
  EXPECT_EQ(q.observations.size(), p.observations.size());
  EXPECT_EQ(q.points.back(), p.points.back());
  o.seed = 5;
  EXPECT_NE(generate_ba_problem(o).points.back(), p.points.back());
}

TEST(BaGenerator, SpecParsing) {
  BaSimOptions o;
  EXPECT_TRUE(parse_ba_sim_spec("sim:ba?cameras=2000&points=500000&seed=3", &o));
  EXPECT_EQ(o.cameras, 2000);
  EXPECT_EQ(o.points, 500000);
  EXPECT_EQ(o.seed, 3u);
  EXPECT_TRUE(parse_ba_sim_spec("sim:ba", &o));
  EXPECT_FALSE(parse_ba_sim_spec("sim:sphere", &o));
  EXPECT_FALSE(parse_ba_sim_spec("sim:bad", &o));
  EXPECT_THROW(parse_ba_sim_spec("sim:ba?cameras=x", &o), InputError);
  EXPECT_THROW(parse_ba_sim_spec("sim:ba?lens=2", &o), InputError);
  BaSimOptions bad;
  bad.cameras = 1;
  EXPECT_THROW(generate_ba_problem(bad), InputError);
}

}  // namespace
}  // namespace slamkit
