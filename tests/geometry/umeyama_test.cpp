// Umeyama alignment: exact recovery of known transforms on synthetic data (1e-9), agreement
// with Eigen's implementation on noisy data, the 4-DoF yaw variant, and degenerate input.
#include "slamkit/geometry/umeyama.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace slamkit {
namespace {

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

Eigen::Matrix3Xd random_points(std::mt19937& rng, int n, double spread = 20.0) {
  std::uniform_real_distribution<double> u(-spread, spread);
  Eigen::Matrix3Xd p(3, n);
  for (int k = 0; k < n; ++k) p.col(k) = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

Eigen::Matrix3Xd transform(const Similarity3& S, const Eigen::Matrix3Xd& p) {
  Eigen::Matrix3Xd out(3, p.cols());
  for (Eigen::Index k = 0; k < p.cols(); ++k) out.col(k) = S.apply(p.col(k));
  return out;
}

Similarity3 random_similarity(std::mt19937& rng, bool with_scale) {
  std::uniform_real_distribution<double> t(-100.0, 100.0), s(0.2, 5.0);
  Similarity3 S;
  S.R = random_rotation(rng);
  S.t = Eigen::Vector3d(t(rng), t(rng), t(rng));
  S.scale = with_scale ? s(rng) : 1.0;
  return S;
}

TEST(Umeyama, RecoversRandomSim3Exactly) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Similarity3 truth = random_similarity(rng, true);
    const Eigen::Matrix3Xd src = random_points(rng, 3 + trial * 7);
    const Similarity3 est = umeyama(src, transform(truth, src), true);
    EXPECT_LT((est.R - truth.R).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    EXPECT_LT((est.t - truth.t).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    EXPECT_NEAR(est.scale, truth.scale, 1e-9 * truth.scale) << "trial " << trial;
    EXPECT_NEAR(est.R.determinant(), 1.0, 1e-12);
  }
}

TEST(Umeyama, RecoversRandomSe3ExactlyWithoutScale) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 50; ++trial) {
    const Similarity3 truth = random_similarity(rng, false);
    const Eigen::Matrix3Xd src = random_points(rng, 10 + trial);
    const Similarity3 est = umeyama(src, transform(truth, src), false);
    EXPECT_LT((est.R - truth.R).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((est.t - truth.t).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_EQ(est.scale, 1.0);
  }
}

TEST(Umeyama, PlanarPointsStillGiveAProperRotation) {
  // Rank-2 covariance (all points in a plane): S must keep det R = +1 (eq. 43).
  std::mt19937 rng(9);
  Eigen::Matrix3Xd src = random_points(rng, 40);
  src.row(2).setZero();
  const Similarity3 truth = random_similarity(rng, true);
  const Similarity3 est = umeyama(src, transform(truth, src), true);
  EXPECT_LT((est.R - truth.R).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(est.scale, truth.scale, 1e-9 * truth.scale);
}

TEST(Umeyama, MatchesEigenOnNoisyData) {
  std::mt19937 rng(10);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (int trial = 0; trial < 20; ++trial) {
    for (bool with_scale : {false, true}) {
      const Similarity3 truth = random_similarity(rng, with_scale);
      const Eigen::Matrix3Xd src = random_points(rng, 200);
      Eigen::Matrix3Xd dst = transform(truth, src);
      for (Eigen::Index k = 0; k < dst.cols(); ++k) dst.col(k) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      const Similarity3 ours = umeyama(src, dst, with_scale);
      const Eigen::Matrix4d eigen = Eigen::umeyama(src, dst, with_scale);
      EXPECT_LT((ours.matrix() - eigen).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial << " scale " << with_scale;
    }
  }
}

TEST(Umeyama, MinimizesTheSquaredError) {
  // Perturbing the optimum in any direction cannot decrease Σ‖y − (sRx + t)‖².
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Matrix3Xd src = random_points(rng, 100);
  Eigen::Matrix3Xd dst = transform(random_similarity(rng, true), src);
  for (Eigen::Index k = 0; k < dst.cols(); ++k) dst.col(k) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const Similarity3 best = umeyama(src, dst, true);
  auto cost = [&](const Similarity3& S) { return (transform(S, src) - dst).squaredNorm(); };
  const double c0 = cost(best);
  for (int k = 0; k < 3; ++k) {
    for (double h : {-1e-4, 1e-4}) {
      Similarity3 p = best;
      p.R = best.R * Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(k)).toRotationMatrix();
      EXPECT_GE(cost(p), c0);
      p = best;
      p.t(k) += h;
      EXPECT_GE(cost(p), c0);
    }
  }
  Similarity3 p = best;
  p.scale *= 1.0001;
  EXPECT_GE(cost(p), c0);
}

TEST(UmeyamaYaw, RecoversYawAndTranslationExactly) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> yaw(-kPi, kPi), t(-50.0, 50.0);
  for (int trial = 0; trial < 50; ++trial) {
    Similarity3 truth;
    truth.R = Eigen::AngleAxisd(yaw(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    truth.t = Eigen::Vector3d(t(rng), t(rng), t(rng));
    const Eigen::Matrix3Xd src = random_points(rng, 5 + trial);
    const Similarity3 est = umeyama_yaw(src, transform(truth, src));
    EXPECT_LT((est.R - truth.R).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((est.t - truth.t).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_EQ(est.scale, 1.0);
    // R is a rotation about z only.
    EXPECT_NEAR(est.R(2, 2), 1.0, 1e-12);
  }
}

TEST(UmeyamaYaw, IsTheBestYawOnNoisyData) {
  // Compare with a dense scan of yaw (translation optimal for each yaw: t = μy − Rz μx).
  std::mt19937 rng(13);
  std::normal_distribution<double> noise(0.0, 0.3);
  const Eigen::Matrix3Xd src = random_points(rng, 80);
  Similarity3 truth;
  truth.R = Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
            Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()).toRotationMatrix();  // a little tilt
  truth.t = Eigen::Vector3d(3, -2, 1);
  Eigen::Matrix3Xd dst = transform(truth, src);
  for (Eigen::Index k = 0; k < dst.cols(); ++k) dst.col(k) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const Similarity3 est = umeyama_yaw(src, dst);
  auto cost = [&](double theta) {
    Similarity3 S;
    S.R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    S.t = dst.rowwise().mean() - S.R * src.rowwise().mean();
    return (transform(S, src) - dst).squaredNorm();
  };
  const double theta = std::atan2(est.R(1, 0), est.R(0, 0));
  const double c_est = (transform(est, src) - dst).squaredNorm();
  EXPECT_NEAR(c_est, cost(theta), 1e-9 * c_est);
  for (int k = 0; k < 3600; ++k) EXPECT_GE(cost(-kPi + k * 2 * kPi / 3600) + 1e-9, c_est);
}

TEST(Umeyama, DegenerateInputThrows) {
  Eigen::Matrix3Xd line(3, 5), two(3, 2), same(3, 4);
  for (int k = 0; k < 5; ++k) line.col(k) = Eigen::Vector3d(k, 2.0 * k, -k);
  two << 0, 1, 0, 1, 0, 1;
  same.setOnes();
  EXPECT_THROW(umeyama(line, line, false), std::invalid_argument);
  EXPECT_THROW(umeyama(two, two, true), std::invalid_argument);
  EXPECT_THROW(umeyama(same, same, true), std::invalid_argument);
  EXPECT_THROW(umeyama(line, Eigen::Matrix3Xd(3, 4), false), std::invalid_argument);
  Eigen::Matrix3Xd vertical(3, 5);
  for (int k = 0; k < 5; ++k) vertical.col(k) = Eigen::Vector3d(1.0, 2.0, k);
  EXPECT_THROW(umeyama_yaw(vertical, vertical), std::invalid_argument);
  Eigen::Matrix3Xd bad = line;
  bad(0, 0) = std::nan("");
  EXPECT_THROW(umeyama(bad, line, false), std::invalid_argument);
}

TEST(Similarity3, InverseAndMatrix) {
  std::mt19937 rng(14);
  const Similarity3 S = random_similarity(rng, true);
  const Eigen::Vector3d p(1.5, -2.0, 0.25);
  EXPECT_LT((S.inverse().apply(S.apply(p)) - p).norm(), 1e-9);
  EXPECT_LT((S.matrix() * p.homogeneous() - S.apply(p).homogeneous()).norm(), 1e-9);
  EXPECT_LT((S.rigid_part().matrix().topLeftCorner<3, 3>() - S.R).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace slamkit
