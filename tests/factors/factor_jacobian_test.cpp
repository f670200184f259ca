// Every factor type's analytic Jacobians against central differences (core/jacobian_check.h),
// and the robust-kernel correction of Factor::linearize against the numeric gradient of ρ.
#include <gtest/gtest.h>

#include <random>

#include "slamkit/core/jacobian_check.h"
#include "slamkit/factors/between_factor.h"
#include "slamkit/factors/pose_point_factor.h"
#include "slamkit/factors/prior_factor.h"

namespace slamkit {
namespace {

SE3 random_se3(std::mt19937& rng, double angle) {
  std::normal_distribution<double> n;
  SE3::Tangent t;
  t << 2 * n(rng), 2 * n(rng), 2 * n(rng), angle * n(rng), angle * n(rng), angle * n(rng);
  return SE3::exp(t);
}

TEST(FactorJacobians, AllFactorTypesMatchNumeric) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n;
  Values v;
  FactorGraph g;
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Random();
  const auto info6 = NoiseModel::information(A * A.transpose() + Eigen::Matrix<double, 6, 6>::Identity());
  const auto info3 = NoiseModel::information(Eigen::Vector3d(2, 3, 4).asDiagonal());
  for (int i = 0; i < 12; ++i) {
    v.insert(symbol('x', i), random_se3(rng, 1.0));
    v.insert(symbol('p', i), SE2(n(rng), n(rng), 2 * n(rng)));
    v.insert(symbol('l', i), Eigen::Vector3d(3 * n(rng), 3 * n(rng), 3 * n(rng)));
    v.insert(symbol('m', i), Eigen::Vector2d(3 * n(rng), 3 * n(rng)));
    v.insert(symbol('r', i), SO3::exp(Eigen::Vector3d(n(rng), n(rng), n(rng))));
  }
  for (int i = 0; i + 1 < 12; ++i) {
    const SE3 z = random_se3(rng, 0.5);
    g.emplace<BetweenFactorSE3>(symbol('x', i), symbol('x', i + 1), z, info6);
    g.emplace<BetweenFactorSE3>(symbol('x', i), symbol('x', i + 1), z, info6, nullptr, Se3ErrorForm::kLog);
    g.emplace<BetweenFactorSE2>(symbol('p', i), symbol('p', i + 1), SE2(n(rng), n(rng), n(rng)), info3);
    g.emplace<PosePointFactor3>(symbol('x', i), symbol('l', i), Eigen::Vector3d(n(rng), n(rng), n(rng)),
                                random_se3(rng, 0.3), NoiseModel::unit(3));
    g.emplace<PosePointFactor2>(symbol('p', i), symbol('m', i), Eigen::Vector2d(n(rng), n(rng)), NoiseModel::unit(2));
    g.emplace<PriorFactor<SE3>>(symbol('x', i), random_se3(rng, 0.5), info6);
    g.emplace<PriorFactor<SE2>>(symbol('p', i), SE2(n(rng), n(rng), n(rng)), info3);
    g.emplace<PriorFactor<SO3>>(symbol('r', i), SO3::exp(Eigen::Vector3d(n(rng), n(rng), n(rng))), NoiseModel::unit(3));
    g.emplace<PriorFactor<Eigen::Vector3d>>(symbol('l', i), Eigen::Vector3d(1, 2, 3), NoiseModel::unit(3));
  }
  const JacobianCheckResult r = check_jacobians(g, v, 1e-6);
  EXPECT_TRUE(r.ok) << r.message();
  EXPECT_EQ(r.factors_checked, g.size());
}

TEST(FactorJacobians, CheckFailsOnAWrongJacobian) {
  // A factor with a deliberately wrong Jacobian must be caught.
  struct Wrong final : FactorN<1, Eigen::Matrix<double, 1, 1>> {
    using FactorN::FactorN;
    Residual error(const Eigen::Matrix<double, 1, 1>& x, Jacobian<Eigen::Matrix<double, 1, 1>>* J) const override {
      if (J) (*J)(0, 0) = 2.0 * x(0);  // derivative of x³ is 3x²
      return Residual(x(0) * x(0) * x(0));
    }
  };
  Values v;
  v.insert(Key{1}, Eigen::Matrix<double, 1, 1>(1.5));
  FactorGraph g;
  g.emplace<Wrong>(std::array<Key, 1>{Key{1}}, nullptr);
  const JacobianCheckResult r = check_jacobians(g, v);
  EXPECT_FALSE(r.ok);
  EXPECT_NEAR(r.numeric, 3.0 * 1.5 * 1.5, 1e-6);
}

TEST(FactorLinearize, RobustCorrectionGivesTheGradientOfRho) {
  // ½ ∂ρ(‖R r(x ⊞ δ)‖²)/∂δ = Ĵᵀ r̂ for every kernel, inside and outside its quadratic zone.
  std::mt19937 rng(9);
  const SE3 Xi = random_se3(rng, 1.0), Xj = random_se3(rng, 1.0), Z = random_se3(rng, 1.0);
  for (const char* name : {"huber", "cauchy", "tukey", "geman-mcclure", "dcs"}) {
    for (double delta : {0.5, 3.0, 50.0}) {
      const BetweenFactorSE3 f(1, 2, Z, NoiseModel::isotropic(6, 0.7), make_robust_kernel(name, delta));
      double pi[7], pj[7];
      ManifoldTraits<SE3>::to_params(Xi, pi);
      ManifoldTraits<SE3>::to_params(Xj, pj);
      const double* params[2] = {pi, pj};
      double r[6], Ji[36], Jj[36];
      double* jac[2] = {Ji, Jj};
      f.linearize(params, r, jac);
      const Eigen::Matrix<double, 6, 1> grad = Eigen::Map<Eigen::Matrix<double, 6, 6>>(Ji).transpose() *
                                               Eigen::Map<Eigen::Matrix<double, 6, 1>>(r);
      for (int c = 0; c < 6; ++c) {
        const double h = 1e-6;
        double pp[7], pm[7], rw[6];
        SE3::Tangent d = SE3::Tangent::Zero();
        d[c] = h;
        ManifoldTraits<SE3>::to_params(Xi.plus(d), pp);
        d[c] = -h;
        ManifoldTraits<SE3>::to_params(Xi.plus(d), pm);
        const double* a[2] = {pp, pj};
        const double* b[2] = {pm, pj};
        const double numeric = 0.5 * (f.cost(a, rw) - f.cost(b, rw)) / (2 * h);
        EXPECT_NEAR(grad[c], numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << name << " δ=" << delta;
      }
    }
  }
}

}  // namespace
}  // namespace slamkit
