// The textbook curve fit y = exp(a x² + b x + c) + w: every step strategy of the Optimizer
// reaches the optimum of an independent dense Gauss-Newton written here from scratch.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "slamkit/factors/exp_curve_factor.h"
#include "slamkit/sim/curve_fitting_data.h"
#include "slamkit/solvers/optimizer.h"

namespace slamkit {
namespace {

// Dense Gauss-Newton on r_i = y_i − exp(a x² + b x + c), started at the truth.
Eigen::Vector3d reference_optimum(const CurveFittingData& d) {
  Eigen::Vector3d t = d.truth;
  for (int it = 0; it < 100; ++it) {
    Eigen::MatrixXd J(d.x.size(), 3);
    Eigen::VectorXd r(d.x.size());
    for (std::size_t i = 0; i < d.x.size(); ++i) {
      const double x = d.x[i], e = std::exp(t[0] * x * x + t[1] * x + t[2]);
      r[i] = d.y[i] - e;
      J.row(i) << -e * x * x, -e * x, -e;
    }
    t -= (J.transpose() * J).ldlt().solve(J.transpose() * r);
  }
  return t;
}

TEST(CurveFitting, EveryStrategyReachesTheReferenceOptimum) {
  const CurveFittingData d = generate_curve_fitting_data(1);
  const Eigen::Vector3d ref = reference_optimum(d);
  FactorGraph g;
  for (std::size_t i = 0; i < d.x.size(); ++i) g.emplace<ExpCurveFactor>(Key{0}, d.x[i], d.y[i], d.sigma);
  for (Algorithm a : {Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM, Algorithm::kDogleg,
                      Algorithm::kGaussNewton}) {
    Values v;
    v.insert(Key{0}, Eigen::Vector3d(2, -1, 5));  // the textbook start
    OptimizerOptions o;
    o.algorithm = a;
    o.num_threads = 1;
    o.function_tolerance = 1e-12;
    const Summary s = Optimizer(o).optimize(g, v);
    EXPECT_TRUE(s.success()) << to_string(a) << ": " << s.message;
    EXPECT_LT((v.at<Eigen::Vector3d>(Key{0}) - ref).norm(), 1e-5) << to_string(a);
  }
  // The figures quoted in docs/bundle_adjustment.md for this draw.
  EXPECT_NEAR(ref[0], 0.693509, 1e-6);
  EXPECT_NEAR(ref[1], 2.392811, 1e-6);
  EXPECT_NEAR(ref[2], 0.893513, 1e-6);
}

}  // namespace
}  // namespace slamkit
