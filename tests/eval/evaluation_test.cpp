// The evaluation pipeline on the real TUM RGB-D and EuRoC pairs (no stored evo results):
// association counts equal an independent brute-force count of evo's rule, every matched
// pair is within max_diff, and the alignment modes obey the inequalities that least squares
// implies (more freedom, smaller SSE); invariance under a known transform of the estimate.
#include "slamkit/eval/evaluation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "slamkit/core/error.h"
#include "slamkit/io/trajectory_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

/// Number of matches of evo's rule, computed the slow way (argmin over the longer trajectory).
std::size_t brute_force_matches(const Trajectory& est, const Trajectory& ref, double max_diff) {
  const bool est_longer = est.size() > ref.size();
  const Trajectory& s = est_longer ? ref : est;
  const Trajectory& l = est_longer ? est : ref;
  std::size_t n = 0;
  for (const auto& a : s) {
    double best = std::abs(l[0].stamp - a.stamp);
    for (const auto& b : l) best = std::min(best, std::abs(b.stamp - a.stamp));
    if (best <= max_diff) ++n;
  }
  return n;
}

EvalResult run(const Trajectory& est, const Trajectory& ref, AlignmentMode align, MetricKind kind = MetricKind::kAte) {
  EvalOptions opt;
  opt.kind = kind;
  opt.align = align;
  return evaluate(est, ref, opt);
}

void check_pair(const std::filesystem::path& est_path, const std::filesystem::path& ref_path, double max_rmse) {
  const Trajectory est = read_trajectory(est_path.string());
  const Trajectory ref = read_trajectory(ref_path.string());
  const EvalResult se3 = run(est, ref, AlignmentMode::kSe3);
  SCOPED_TRACE(est_path.filename().string());
  // Association: count from the rule, |Δt| ≤ 10 ms for every pair.
  EXPECT_EQ(se3.association.size(), brute_force_matches(est, ref, 0.01));
  EXPECT_FALSE(se3.association.by_index);
  for (std::size_t k = 0; k < se3.association.size(); ++k)
    EXPECT_LE(std::abs(est[se3.association.est_ids[k]].stamp - ref[se3.association.ref_ids[k]].stamp), 0.01);
  EXPECT_EQ(se3.stats.count, se3.association.size());
  EXPECT_GT(se3.stats.rmse, 0.0);
  EXPECT_LT(se3.stats.rmse, max_rmse);
  EXPECT_LE(se3.stats.min, se3.stats.median);
  EXPECT_LE(se3.stats.median, se3.stats.max);

  // Least squares: SSE(sim3) ≤ SSE(se3) ≤ SSE(4dof), and se3 beats the non-optimal alignments.
  const double sse_se3 = se3.stats.sse;
  EXPECT_LE(run(est, ref, AlignmentMode::kSim3).stats.sse, sse_se3 * (1 + 1e-12));
  EXPECT_GE(run(est, ref, AlignmentMode::kPosYaw).stats.sse, sse_se3 * (1 - 1e-12));
  EXPECT_GE(run(est, ref, AlignmentMode::kOrigin).stats.sse, sse_se3);
  EXPECT_GE(run(est, ref, AlignmentMode::kNone).stats.sse, sse_se3);

  // Moving the estimate rigidly does not change the SE(3)-aligned ATE nor any RPE; scaling it
  // does not change the Sim(3)-aligned ATE.
  const SE3 S(SO3::from_rpy(0.4, -0.3, 2.0), Eigen::Vector3d(12, -7, 3));
  Trajectory moved = est, scaled = est;
  for (std::size_t k = 0; k < est.size(); ++k) {
    moved[k].T_world_body = S * est[k].T_world_body;
    scaled[k].T_world_body = SE3(est[k].T_world_body.rotation(), 3.0 * est[k].T_world_body.translation());
  }
  EXPECT_NEAR(run(moved, ref, AlignmentMode::kSe3).stats.rmse, se3.stats.rmse, 1e-9);
  EXPECT_NEAR(run(scaled, ref, AlignmentMode::kSim3).stats.rmse, run(est, ref, AlignmentMode::kSim3).stats.rmse, 1e-9);
  EXPECT_NEAR(run(moved, ref, AlignmentMode::kNone, MetricKind::kRpe).stats.rmse,
              run(est, ref, AlignmentMode::kNone, MetricKind::kRpe).stats.rmse, 1e-9);
}

TEST(Evaluation, TumRgbdFr2DeskOrb) {
  SLAMKIT_REQUIRE_DATA(est, "vio/eval_reference/fr2_desk_ORB.txt");
  SLAMKIT_REQUIRE_DATA(ref, "vio/eval_reference/fr2_desk_groundtruth.txt");
  check_pair(est, ref, 0.05);
}

TEST(Evaluation, TumRgbdFr1XyzRgbdslam) {
  SLAMKIT_REQUIRE_DATA(est, "vio/eval_reference/freiburg1_xyz-rgbdslam.txt");
  SLAMKIT_REQUIRE_DATA(ref, "vio/eval_reference/freiburg1_xyz-groundtruth.txt");
  check_pair(est, ref, 0.05);
}

TEST(Evaluation, EurocV102SecondsAgainstNanoseconds) {
  SLAMKIT_REQUIRE_DATA(est, "vio/eval_reference/V102.txt");
  SLAMKIT_REQUIRE_DATA(ref, "vio/euroc/gt/V1_02_medium_gt.csv");
  check_pair(est, ref, 0.3);
  // The reference has exact ns stamps, the estimate seconds; 4 estimate stamps are repeated.
  const Trajectory e = read_trajectory(est.string()), r = read_trajectory(ref.string());
  EXPECT_TRUE(r.has_stamps_ns());
  const EvalResult rpe = run(e, r, AlignmentMode::kNone, MetricKind::kRpe);
  EXPECT_EQ(rpe.pairs.size() + 1, rpe.association.size());  // 1-frame consecutive pairs
}

TEST(Evaluation, RpeDeltaUnitsOnKitti) {
  SLAMKIT_REQUIRE_DATA(gt, "vio/eval_reference/KITTI_00_gt.txt");
  SLAMKIT_REQUIRE_DATA(orb, "vio/eval_reference/KITTI_00_ORB.txt");
  const Trajectory ref = read_trajectory(gt.string()), est = read_trajectory(orb.string());
  EvalOptions opt;
  opt.kind = MetricKind::kRpe;
  for (DeltaUnit u : {DeltaUnit::kFrames, DeltaUnit::kMeters, DeltaUnit::kDegrees, DeltaUnit::kRadians}) {
    opt.rpe.delta_unit = u;
    opt.rpe.delta = u == DeltaUnit::kFrames ? 10 : u == DeltaUnit::kMeters ? 10.0 : u == DeltaUnit::kDegrees ? 5.0 : 5.0 * kPi / 180;
    for (bool all : {false, true}) {
      opt.rpe.all_pairs = all;
      const EvalResult r = evaluate(est, ref, opt);
      SCOPED_TRACE(std::string(long_name(u)) + (all ? " all pairs" : " consecutive"));
      EXPECT_GT(r.pairs.size(), 10u);
      EXPECT_GT(r.stats.rmse, 0.0);
      EXPECT_LT(r.stats.rmse, 5.0);
    }
  }
  // Degrees and the same angle in radians select the same pairs.
  opt.rpe.all_pairs = false;
  opt.rpe.delta_unit = DeltaUnit::kDegrees;
  opt.rpe.delta = 5.0;
  const auto deg = evaluate(est, ref, opt).pairs;
  opt.rpe.delta_unit = DeltaUnit::kRadians;
  opt.rpe.delta = 5.0 * kPi / 180;
  EXPECT_EQ(evaluate(est, ref, opt).pairs, deg);
  // Seconds need timestamps, which KITTI has not.
  opt.rpe.delta_unit = DeltaUnit::kSeconds;
  EXPECT_THROW(evaluate(est, ref, opt), Error);
}

}  // namespace
}  // namespace slamkit
