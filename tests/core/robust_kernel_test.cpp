#include "slamkit/core/robust_kernel.h"

#include <gtest/gtest.h>

#include "slamkit/core/error.h"
#include "slamkit/core/noise_model.h"

namespace slamkit {
namespace {

TEST(RobustKernel, DerivativesMatchNumericAndLeastSquaresNearZero) {
  for (const char* name : {"huber", "cauchy", "tukey", "geman-mcclure", "dcs"}) {
    const auto k = make_robust_kernel(name, 1.3);
    for (double s : {1e-6, 0.3, 1.0, 1.6, 1.7, 4.0, 25.0}) {
      if (std::string(name) == "huber" && std::abs(s - 1.69) < 0.05) continue;  // kink of ρ'' at δ²
      double r[3], rp[3], rm[3];
      const double h = 1e-6 * std::max(1.0, s);
      k->evaluate(s, r);
      k->evaluate(s + h, rp);
      k->evaluate(s - h, rm);
      EXPECT_NEAR(r[1], (rp[0] - rm[0]) / (2 * h), 1e-6) << name << " s=" << s;
      EXPECT_NEAR(r[2], (rp[1] - rm[1]) / (2 * h), 1e-5) << name << " s=" << s;
    }
    double r[3];
    k->evaluate(1e-8, r);
    EXPECT_NEAR(r[0], 1e-8, 1e-12) << name;
    EXPECT_NEAR(r[1], 1.0, 1e-6) << name;
  }
}

TEST(RobustKernel, ParsesSpecsAndRejectsBadOnes) {
  EXPECT_EQ(parse_robust_kernel("cauchy:0.5")->name(), "cauchy");
  EXPECT_DOUBLE_EQ(parse_robust_kernel("huber:2")->delta(), 2.0);
  EXPECT_THROW(parse_robust_kernel("huber"), InputError);
  EXPECT_THROW(parse_robust_kernel("huber:x"), InputError);
  EXPECT_THROW(parse_robust_kernel("nope:1"), InputError);
  EXPECT_THROW(parse_robust_kernel("huber:-1"), InputError);
}

TEST(NoiseModel, WhitenedNormIsMahalanobis) {
  Eigen::Matrix3d omega;
  omega << 4, 1, 0.5, 1, 3, 0.2, 0.5, 0.2, 2;
  const auto n = NoiseModel::information(omega);
  EXPECT_EQ(n->kind(), NoiseModel::Kind::kDense);
  Eigen::Vector3d r(0.3, -1.2, 2.0);
  const double expected = r.dot(omega * r);
  n->whiten(r.data());
  EXPECT_NEAR(r.squaredNorm(), expected, 1e-12);
  EXPECT_TRUE(n->information_matrix().isApprox(omega, 1e-12));
  EXPECT_EQ(NoiseModel::information(Eigen::Matrix3d(Eigen::Vector3d(1, 2, 3).asDiagonal()))->kind(),
            NoiseModel::Kind::kDiagonal);
  Eigen::Matrix3d bad = omega;
  bad(2, 2) = -5;
  EXPECT_THROW(NoiseModel::information(bad), NumericalError);
}

}  // namespace
}  // namespace slamkit
