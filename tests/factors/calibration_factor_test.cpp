// Calibration factors: analytic Jacobians against central differences (including straight
// and in-place differential-drive motion), and calibration inside optimize_pose_graph on
// generated problems: accuracy, consistency with the marginal sigmas, calibration off, and
// the unobservable straight line.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamkit/core/jacobian_check.h"
#include "slamkit/factors/calibration_factors.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/sim/calibration_generator.h"

namespace slamkit {
namespace {

SE3 random_se3(std::mt19937& rng, double angle) {
  std::normal_distribution<double> n;
  SE3::Tangent t;
  t << n(rng), n(rng), n(rng), angle * n(rng), angle * n(rng), angle * n(rng);
  return SE3::exp(t);
}

TEST(CalibrationFactors, JacobiansMatchNumeric) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n;
  Values v;
  FactorGraph g;
  const auto info3 = NoiseModel::information(Eigen::Vector3d(2, 3, 4).asDiagonal());
  const auto info6 = NoiseModel::unit(6);
  for (int i = 0; i < 8; ++i) {
    v.insert(symbol('p', i), SE2(n(rng), n(rng), 2 * n(rng)));
    v.insert(symbol('x', i), random_se3(rng, 1.0));
  }
  v.insert(symbol('s', 0), SE2(0.3, -0.1, 0.4));
  v.insert(symbol('s', 1), SE2(-0.2, 0.5, -1.0));
  v.insert(symbol('o', 0), random_se3(rng, 0.5));
  v.insert(symbol('o', 1), random_se3(rng, 0.5));
  v.insert(symbol('k', 0), Eigen::Vector3d(1.05, 0.97, 0.52));
  Vector9d K = identity_linear_odometry();
  for (int k = 0; k < 9; ++k) K[k] += 0.1 * n(rng);
  v.insert(symbol('k', 1), K);
  // Wheel readings: turning, straight (θ = 0 exactly), nearly straight, in place.
  const Eigen::Vector3d wheels[] = {{0.9, 1.2, 0.5}, {1.0, 1.0, 0.5}, {1.0, 1.0 + 1e-6, 0.5}, {-0.3, 0.3, 0.5}};
  for (int i = 0; i + 1 < 8; ++i) {
    const Key a = symbol('p', i), b = symbol('p', i + 1);
    g.emplace<SensorOffsetFactor<SE2>>(a, b, symbol('s', 0), SE2(n(rng), n(rng), n(rng)), info3);
    g.emplace<SensorOffsetPairFactor<SE2>>(a, b, symbol('s', 0), symbol('s', 1), SE2(n(rng), n(rng), n(rng)), info3);
    g.emplace<SensorOffsetFactor<SE3>>(symbol('x', i), symbol('x', i + 1), symbol('o', 0), random_se3(rng, 0.5), info6);
    g.emplace<SensorOffsetPairFactor<SE3>>(symbol('x', i), symbol('x', i + 1), symbol('o', 0), symbol('o', 1),
                                           random_se3(rng, 0.5), info6);
    g.emplace<DifferentialDriveOdometryFactor>(a, b, symbol('k', 0), wheels[i % 4], info3);
    g.emplace<LinearOdometryFactor>(a, b, symbol('k', 1), Eigen::Vector3d(n(rng), n(rng), n(rng)), info3);
  }
  g.emplace<PriorFactor<Eigen::Vector3d>>(symbol('k', 0), Eigen::Vector3d(1, 1, 0.5), info3);
  g.emplace<PriorFactor<SE2>>(symbol('s', 0), SE2(0.2, 0, 0), info3);
  g.emplace<PriorFactor<Vector9d>>(symbol('k', 1), identity_linear_odometry(), NoiseModel::unit(9));
  const JacobianCheckResult r = check_jacobians(g, v, 1e-6);
  EXPECT_TRUE(r.ok) << r.message();
  EXPECT_EQ(r.factors_checked, g.size());
}

TEST(CalibrationFactors, DifferentialDriveMotionMatchesTheArc) {
  // Left wheel 0.9 m, right 1.1 m, baseline 0.5: θ = 0.4, radius = d/θ = 2.5 m.
  const Eigen::Vector3d u = differential_drive_motion(Eigen::Vector3d(1, 1, 0.5), 0.9, 1.1, 1.0);
  EXPECT_NEAR(u[2], 0.4, 1e-15);
  EXPECT_NEAR(u[0], 2.5 * std::sin(0.4), 1e-14);
  EXPECT_NEAR(u[1], 2.5 * (1 - std::cos(0.4)), 1e-14);
  const Eigen::Vector3d s = differential_drive_motion(Eigen::Vector3d(2, 2, 0.5), 1.0, 1.0, 0.5);
  EXPECT_NEAR(s[0], 1.0, 1e-15);
  EXPECT_EQ(s[1], 0.0);
}

PoseGraphResult optimize(PoseGraph g, bool calibrate) {
  PoseGraphOptimizerOptions o;
  if (!calibrate) o.problem.calibration.offsets = o.problem.calibration.odometry = false;
  return optimize_pose_graph(g, o);
}

TEST(CalibrationOptimize, Calib2dRecoversTheTruthWithinItsSigmas) {
  CalibrationSimOptions so;
  so.seed = 3;
  CalibrationTruth truth;
  const PoseGraph g = generate_calibration_problem(so, &truth);
  const PoseGraphResult on = optimize(g, true);
  ASSERT_EQ(on.calibration.parameters.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    const CalibrationParameterEstimate& p = on.calibration.parameters[i];
    EXPECT_EQ(p.name, truth[i].first);
    EXPECT_TRUE(p.observable) << p.name;
    EXPECT_LT(std::abs(p.value - truth[i].second), 4 * p.sigma) << p.name;
  }
  EXPECT_LT(std::abs(on.calibration.parameters[0].value - truth[0].second), 0.01);
  EXPECT_LT(std::abs(on.calibration.parameters[2].value - truth[2].second), 0.2 * kPi / 180);
  EXPECT_LT(std::abs(on.calibration.parameters[5].value / truth[5].second - 1), 0.005);
  EXPECT_TRUE(on.calibration.warnings.empty());
  const PoseGraphResult off = optimize(g, false);
  EXPECT_TRUE(off.calibration.parameters.empty());
  EXPECT_GT(off.final_chi2, 3 * on.final_chi2);
}

TEST(CalibrationOptimize, LinearOdometryModelAbsorbsTheWheelErrors) {
  CalibrationSimOptions so;
  so.odometry = "linear";
  so.seed = 2;
  CalibrationTruth truth;
  const PoseGraph g = generate_calibration_problem(so, &truth);
  ASSERT_EQ(g.calibration.vertices[1].kind, CalibrationKind::kOdomLinear);
  const PoseGraphResult on = optimize(g, true), off = optimize(g, false);
  ASSERT_EQ(on.calibration.parameters.size(), 12u);  // offset (3) + K (9)
  EXPECT_GT(off.final_chi2, 2 * on.final_chi2);
  // A K that rotates (Δx, Δy) turns the body frame just as the offset angle does: the block is
  // (nearly) rank-deficient by one, and the check must hold one of the two instead of returning
  // an arbitrary split.
  bool angle_or_rotation_held = false;
  for (const std::string& h : on.calibration.held)
    angle_or_rotation_held |= h.find(".theta") != std::string::npos || h.find(".K21") != std::string::npos;
  EXPECT_TRUE(angle_or_rotation_held);
  EXPECT_FALSE(on.calibration.warnings.empty());
  // Δy of a differential drive is a function of Δx and Δθ: its column (K12, K22, K32) is barely
  // excited; whatever is held, the chi2 must reach the noise level (about the residual count).
  EXPECT_LT(on.final_chi2, 1.3 * 3.0 * static_cast<double>(g.edges.size()));
}

TEST(CalibrationOptimize, Calib3dRecoversTheOffset) {
  CalibrationSimOptions so;
  so.world = "calib3d";
  so.laps = 3;
  CalibrationTruth truth;
  const PoseGraph g = generate_calibration_problem(so, &truth);
  const PoseGraphResult r = optimize(g, true);
  ASSERT_EQ(r.calibration.parameters.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_LT(std::abs(r.calibration.parameters[i].value - truth[i].second), 4 * r.calibration.parameters[i].sigma)
        << truth[i].first;
}

TEST(CalibrationOptimize, StraightLineWarnsAboutTheBaselineAndTheOffsetTranslation) {
  CalibrationSimOptions so;
  so.path = "line";
  so.laps = 1;
  const PoseGraph g = generate_calibration_problem(so);
  const PoseGraphResult r = optimize(g, true);
  auto warned = [&](const std::string& suffix) {
    for (const std::string& w : r.calibration.warnings)
      if (w.find(suffix) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned(".baseline is unobservable"));
  EXPECT_TRUE(warned(".x is unobservable"));
  EXPECT_FALSE(warned(".k_left"));
  for (const CalibrationParameterEstimate& p : r.calibration.parameters) {
    if (p.name.find("baseline") != std::string::npos) {
      EXPECT_FALSE(p.observable);
      EXPECT_TRUE(std::isnan(p.sigma));
      EXPECT_EQ(p.value, 0.5);  // held at the nominal value, not drifted
    }
  }
}

}  // namespace
}  // namespace slamkit
