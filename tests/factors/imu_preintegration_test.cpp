// IMU preintegration: bias Jacobians and ImuFactor Jacobians against central differences,
// an analytic motion reproduced by integration, the covariance against Monte-Carlo noise,
// and bad input.
#include <gtest/gtest.h>

#include <random>

#include "slamkit/core/error.h"
#include "slamkit/core/jacobian_check.h"
#include "slamkit/factors/imu_preintegration.h"
#include "testing/imu_motion.h"
#include "testing/numeric_jacobian.h"

namespace slamkit {
namespace {

using testing::AnalyticMotion;

ImuPreintegration integrate(const std::vector<ImuMeasurement>& s, const ImuBias& b, const ImuNoise& n = {}) {
  ImuPreintegration pim(b, n);
  for (std::size_t k = 0; k + 1 < s.size(); ++k)
    pim.integrate(s[k + 1].stamp - s[k].stamp, s[k].gyro, s[k].accel, s[k + 1].gyro, s[k + 1].accel);
  return pim;
}

TEST(ImuPreintegration, BiasJacobiansMatchNumeric) {
  const AnalyticMotion motion;
  const std::vector<ImuMeasurement> s = motion.samples(0.2, 1.2, 200.0);
  const ImuBias b0{Eigen::Vector3d(0.01, -0.02, 0.015), Eigen::Vector3d(0.1, -0.05, 0.2)};
  const ImuPreintegration pim = integrate(s, b0);
  const testing::TangentMap g = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    ImuBias b = b0;
    b.gyro += d.head<3>(), b.accel += d.tail<3>();
    const ImuPreintegration q = integrate(s, b);
    Eigen::Matrix<double, 9, 1> e;
    e << q.delta_R().minus(pim.delta_R()), q.delta_v() - pim.delta_v(), q.delta_p() - pim.delta_p();
    return e;
  };
  EXPECT_TRUE(testing::jacobians_match(pim.bias_jacobian(), testing::numeric_jacobian(g, 6), 1e-6, "bias Jacobian"));
  // The first-order correction agrees with re-integration for a small bias change.
  ImuBias b1 = b0;
  b1.gyro += Eigen::Vector3d(1e-3, -2e-3, 1e-3), b1.accel += Eigen::Vector3d(0.01, 0.02, -0.01);
  const ImuPreintegration q = integrate(s, b1);
  // (the error left is second order: below 1 % of the change itself)
  EXPECT_LT(pim.delta_R(b1).minus(q.delta_R()).norm(), 0.01 * q.delta_R().minus(pim.delta_R()).norm());
  EXPECT_LT((pim.delta_v(b1) - q.delta_v()).norm(), 0.01 * (q.delta_v() - pim.delta_v()).norm());
  EXPECT_LT((pim.delta_p(b1) - q.delta_p()).norm(), 0.01 * (q.delta_p() - pim.delta_p()).norm());
}

TEST(ImuPreintegration, IntegratingAnAnalyticMotionReproducesIt) {
  const AnalyticMotion motion;
  const ImuBias bias{Eigen::Vector3d(0.02, -0.01, 0.03), Eigen::Vector3d(-0.1, 0.2, 0.05)};
  const std::vector<ImuMeasurement> s = motion.samples(0.0, 2.0, 200.0, bias);
  ImuPreintegration pim(bias, ImuNoise::tumvi());
  pim.integrate_between(s, 0.3125, 1.3125);  // ends between samples: interpolated
  EXPECT_NEAR(pim.dt(), 1.0, 1e-12);
  const ImuState xi = motion.state(0.3125, bias), xj_true = motion.state(1.3125, bias);
  const ImuState xj = pim.predict(xi, motion.gravity);
  EXPECT_LT(xj.R.minus(xj_true.R).norm(), 2e-6);
  EXPECT_LT((xj.v - xj_true.v).norm(), 2e-5);
  EXPECT_LT((xj.p - xj_true.p).norm(), 2e-5);
  // The factor's residual at the true states is (near) zero; a 1 cm offset is not.
  const ImuFactor f(1, 2, pim, motion.gravity);
  const Eigen::Matrix<double, 15, 1> r = f.error(xi, xj_true, nullptr, nullptr);
  EXPECT_LT(r.norm(), 3e-5);
  ImuState off = xj_true;
  off.p.x() += 0.01;
  EXPECT_GT(f.error(xi, off, nullptr, nullptr).segment<3>(6).norm(), 0.009);
}

TEST(ImuFactor, JacobiansMatchNumeric) {
  const AnalyticMotion motion;
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  const auto rnd = [&](double s) { return Eigen::Vector3d(s * n(rng), s * n(rng), s * n(rng)); };
  Values v;
  FactorGraph g;
  for (int i = 0; i < 6; ++i) {
    const double t0 = 0.4 * i, t1 = t0 + 0.5;
    const ImuBias lin{rnd(0.01), rnd(0.1)};
    const ImuPreintegration pim = integrate(motion.samples(t0, t1, 200.0), lin);
    ImuState xi = motion.state(t0), xj = motion.state(t1);
    // Away from the solution and from the linearization bias, so every term is exercised.
    xi.R = xi.R.plus(rnd(0.3)), xj.R = xj.R.plus(rnd(0.3));
    xi.p += rnd(0.5), xj.p += rnd(0.5), xi.v += rnd(0.5), xj.v += rnd(0.5);
    xi.bg = lin.gyro + rnd(0.02), xi.ba = lin.accel + rnd(0.2), xj.bg = rnd(0.02), xj.ba = rnd(0.2);
    v.insert(symbol('x', 2 * i), xi);
    v.insert(symbol('x', 2 * i + 1), xj);
    g.emplace<ImuFactor>(symbol('x', 2 * i), symbol('x', 2 * i + 1), pim, motion.gravity);
  }
  const JacobianCheckResult r = check_jacobians(g, v, 1e-6);
  EXPECT_TRUE(r.ok) << r.message();
  EXPECT_EQ(r.factors_checked, g.size());
}

TEST(ImuFactor, JacobianCheckCatchesAWrongBlock) {
  // The numeric comparison used above must fail when one analytic block is slightly off.
  const AnalyticMotion motion;
  const ImuPreintegration pim = integrate(motion.samples(0.0, 0.5, 200.0), {});
  const ImuFactor f(1, 2, pim, motion.gravity);
  ImuState xi = motion.state(0.0), xj = motion.state(0.5);
  xi.R = xi.R.plus(Eigen::Vector3d(0.2, -0.1, 0.3));
  Eigen::Matrix<double, 15, 15> Ji, Jj;
  f.error(xi, xj, &Ji, &Jj);
  const testing::TangentMap g = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    return f.error(xi.plus(d), xj, nullptr, nullptr);
  };
  const Eigen::MatrixXd numeric = testing::numeric_jacobian(g, 15);
  EXPECT_TRUE(testing::jacobians_match(Ji, numeric, 1e-6));
  Eigen::MatrixXd wrong = Ji;
  wrong.block<3, 3>(3, 0) *= 1.01;  // a 1 % error in ∂r_v/∂φ_i must be caught
  EXPECT_FALSE(testing::jacobians_match(wrong, numeric, 1e-6));
}

TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  // Noisy IMU (white noise σ·√f per sample, bias random walk σ_w·√dt per step) on the analytic
  // motion; the 15-dof residual at the true states must have NEES ≈ 15 on average.
  const AnalyticMotion motion;
  const ImuNoise noise{2e-3, 2e-2, 1e-3, 1e-2};  // inflated so that the noise dominates the midpoint error
  const double rate = 200.0, dt = 1.0 / rate;
  std::mt19937 rng(11);
  std::normal_distribution<double> n;
  const auto rnd = [&](double s) { return Eigen::Vector3d(s * n(rng), s * n(rng), s * n(rng)); };
  const int runs = 400;
  double nees = 0.0, nees9 = 0.0;
  for (int run = 0; run < runs; ++run) {
    ImuBias b{rnd(0.01), rnd(0.05)};
    const ImuBias b_i = b;
    std::vector<ImuMeasurement> s = motion.samples(0.5, 1.5, rate);
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (k > 0) b.gyro += rnd(noise.gyro_random_walk * std::sqrt(dt)), b.accel += rnd(noise.accel_random_walk * std::sqrt(dt));
      s[k].gyro += b.gyro + rnd(noise.gyro_noise_density * std::sqrt(rate));
      s[k].accel += b.accel + rnd(noise.accel_noise_density * std::sqrt(rate));
    }
    const ImuPreintegration pim = integrate(s, b_i, noise);
    const ImuFactor f(1, 2, pim, motion.gravity);
    const Eigen::Matrix<double, 15, 1> r = f.error(motion.state(0.5, b_i), motion.state(1.5, b), nullptr, nullptr);
    nees += r.dot(pim.covariance().ldlt().solve(r)) / runs;
    nees9 += r.head<9>().dot(pim.covariance().topLeftCorner<9, 9>().ldlt().solve(r.head<9>())) / runs;
  }
  // χ²₁₅ mean over 400 runs: 15 ± 0.27 (1σ); χ²₉: 9 ± 0.21.
  EXPECT_NEAR(nees, 15.0, 1.5);
  EXPECT_NEAR(nees9, 9.0, 1.0);
}

TEST(ImuPreintegration, BadInput) {
  const AnalyticMotion motion;
  const std::vector<ImuMeasurement> s = motion.samples(0.0, 1.0, 200.0);
  ImuPreintegration pim({}, ImuNoise::tumvi());
  EXPECT_THROW(pim.integrate_between(s, 0.5, 1.5), std::invalid_argument);   // not covered
  EXPECT_THROW(pim.integrate_between(s, 0.5, 0.5), std::invalid_argument);   // empty interval
  EXPECT_THROW(pim.integrate(0.0, s[0].gyro, s[0].accel, s[1].gyro, s[1].accel), std::invalid_argument);
  ImuNoise bad;
  bad.gyro_noise_density = std::nan("");
  EXPECT_THROW(ImuPreintegration({}, bad), std::invalid_argument);
  // A factor over no time has no covariance to whiten with.
  EXPECT_THROW(ImuFactor(1, 2, ImuPreintegration({}, ImuNoise::tumvi()), motion.gravity), NumericalError);
}

}  // namespace
}  // namespace slamkit
