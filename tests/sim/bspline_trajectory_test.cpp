// Cumulative cubic B-spline on SO(3) × R³: analytic derivatives against central differences,
// exact recovery of a spline from its own samples, and the fit error on real ground truth.
#include "slamkit/sim/bspline_trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamkit/core/error.h"
#include "slamkit/io/trajectory_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

BSplineTrajectory random_spline(int n, double dt, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  std::vector<SO3> R;
  std::vector<Eigen::Vector3d> P;
  SO3 r;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    r = r * SO3::exp(0.3 * Eigen::Vector3d(N(rng), N(rng), N(rng)));
    p += 0.2 * Eigen::Vector3d(N(rng), N(rng), N(rng));
    R.push_back(r), P.push_back(p);
  }
  return BSplineTrajectory(1.5, dt, R, P);
}

TEST(BSplineTrajectory, DerivativesMatchCentralDifferences) {
  const BSplineTrajectory s = random_spline(12, 0.1, 7);
  const double h = 1e-5;
  for (double t = s.start_time() + 2 * h; t < s.end_time() - 2 * h; t += 0.0173) {
    const BSplineState x = s.evaluate(t);
    const BSplineState xm = s.evaluate(t - h), xp = s.evaluate(t + h);
    const Eigen::Vector3d v_num = (xp.T_world_body.translation() - xm.T_world_body.translation()) / (2 * h);
    const Eigen::Vector3d a_num = (xp.v_world - xm.v_world) / (2 * h);
    const Eigen::Vector3d a_num2 = (xp.T_world_body.translation() - 2 * x.T_world_body.translation() +
                                    xm.T_world_body.translation()) / (h * h);
    // Rᵀ Ṙ = [ω]×: ω ≈ Log(R(t − h)⁻¹ R(t + h)) / 2h (to O(h²)).
    const Eigen::Vector3d w_num = xm.T_world_body.rotation().between(xp.T_world_body.rotation()).log() / (2 * h);
    EXPECT_LT((x.v_world - v_num).norm(), 1e-6 * (1 + v_num.norm())) << t;
    EXPECT_LT((x.a_world - a_num).norm(), 1e-5 * (1 + a_num.norm())) << t;
    EXPECT_LT((x.a_world - a_num2).norm(), 1e-2 * (1 + a_num.norm())) << t;
    EXPECT_LT((x.omega_body - w_num).norm(), 1e-6 * (1 + w_num.norm())) << t;
    EXPECT_NEAR((x.a_body() - x.T_world_body.rotation().matrix().transpose() * x.a_world).norm(), 0.0, 1e-12);
  }
}

TEST(BSplineTrajectory, ContinuousAcrossKnots) {
  const BSplineTrajectory s = random_spline(10, 0.2, 3);
  for (int k = 1; k < 7; ++k) {
    const double t = s.start_time() + k * s.knot_spacing();
    const BSplineState a = s.evaluate(t - 1e-9), b = s.evaluate(t + 1e-9);
    EXPECT_LT((a.T_world_body.translation() - b.T_world_body.translation()).norm(), 1e-7);
    EXPECT_LT((a.a_world - b.a_world).norm(), 1e-5);
    EXPECT_LT((a.omega_body - b.omega_body).norm(), 1e-6);
  }
}

TEST(BSplineTrajectory, FitRecoversASplineFromItsSamples) {
  const BSplineTrajectory truth = random_spline(30, 0.1, 11);
  Trajectory path;
  for (double t = truth.start_time(); t <= truth.end_time(); t += 0.01) path.push_back(t, truth.pose(t));
  BSplineFitOptions opt;
  opt.knot_spacing = 0.1;
  opt.smoothness_weight = 0.0;
  BSplineFitReport rep;
  const BSplineTrajectory fit = BSplineTrajectory::fit(path, opt, &rep);
  EXPECT_EQ(rep.samples, path.size());
  EXPECT_LT(rep.position_rmse, 1e-9);
  EXPECT_LT(rep.rotation_rmse, 1e-8);
  const double t = 0.5 * (fit.start_time() + fit.end_time());
  EXPECT_LT((fit.evaluate(t).omega_body - truth.evaluate(t).omega_body).norm(), 1e-5);
}

TEST(BSplineTrajectory, RejectsBadInput) {
  EXPECT_THROW(random_spline(12, 0.1, 1).evaluate(100.0), std::out_of_range);
  EXPECT_THROW(random_spline(12, 0.1, 1).evaluate(NAN), std::out_of_range);
  EXPECT_THROW(BSplineTrajectory(0, 0.1, {SO3(), SO3(), SO3()}, std::vector<Eigen::Vector3d>(3)), std::invalid_argument);
  Trajectory one;
  one.push_back(0.0, SE3());
  EXPECT_THROW(BSplineTrajectory::fit(one), InputError);
}

// Fit error on the first 40 s of real motion at 0.1 s knots (printed; the bounds are a few
// times the measured values; `slamkit simulate` reports the fit of whole sequences).
void check_real_fit(const std::filesystem::path& file, double max_pos_rmse, double max_rot_rmse) {
  const Trajectory full = read_trajectory(file.string(), TrajectoryFormat::kEuroc);
  Trajectory gt;
  for (const auto& s : full)
    if (s.stamp < full[0].stamp + 40.0) gt.push_back(s);
  BSplineFitReport rep;
  const BSplineTrajectory s = BSplineTrajectory::fit(gt, {}, &rep);
  std::printf("%s: %zu samples, %zu control points, %d iterations: position RMSE %.2f mm (max %.2f), "
              "rotation RMSE %.3f deg (max %.3f)\n",
              file.filename().c_str(), rep.samples, rep.control_points, rep.iterations, 1e3 * rep.position_rmse,
              1e3 * rep.position_max, rep.rotation_rmse * 180 / M_PI, rep.rotation_max * 180 / M_PI);
  EXPECT_EQ(rep.samples, gt.size());
  EXPECT_LT(rep.position_rmse, max_pos_rmse);
  EXPECT_LT(rep.rotation_rmse, max_rot_rmse);
  EXPECT_LE(s.start_time(), gt[0].stamp);
  EXPECT_GE(s.end_time(), gt[gt.size() - 1].stamp);
}

TEST(BSplineTrajectory, FitsTumViRoom1GroundTruth) {
  SLAMKIT_REQUIRE_DATA(file, "vio/tumvi/gt/dataset-room1_512_16.csv");
  check_real_fit(file, 0.005, 0.01);
}

TEST(BSplineTrajectory, FitsEurocV102GroundTruth) {
  SLAMKIT_REQUIRE_DATA(file, "vio/euroc/gt/V1_02_medium_gt.csv");
  check_real_fit(file, 0.005, 0.01);
}

}  // namespace
}  // namespace slamkit
