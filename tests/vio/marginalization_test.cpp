// Marginalization by the Schur complement: on a linear-Gaussian problem, the prior left by
// marginalizing a "keyframe" and the "features" anchored in it reproduces the full problem's
// solution of the remaining variables exactly; and the prior's Jacobians match numeric ones
// at its linearization point.
#include <gtest/gtest.h>

#include <random>

#include "slamkit/core/jacobian_check.h"
#include "slamkit/factors/imu_state.h"
#include "slamkit/factors/marginalization_prior.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/solvers/optimizer.h"
#include "slamkit/vio/marginalization.h"

namespace slamkit {
namespace {

using Vec3 = Eigen::Vector3d;
using Vec1 = Eigen::Matrix<double, 1, 1>;

// r = A x_i + B x_j − z (linear in both states).
class LinearPair final : public FactorN<3, Vec3, Vec3> {
 public:
  LinearPair(Key i, Key j, Eigen::Matrix3d A, Eigen::Matrix3d B, Vec3 z)
      : FactorN({i, j}, NoiseModel::isotropic(3, 0.5)), A_(A), B_(B), z_(z) {}
  Residual error(const Vec3& xi, const Vec3& xj, Jacobian<Vec3>* Ji, Jacobian<Vec3>* Jj) const override {
    if (Ji) *Ji = A_;
    if (Jj) *Jj = B_;
    return A_ * xi + B_ * xj - z_;
  }

 private:
  Eigen::Matrix3d A_, B_;
  Vec3 z_;
};

// A "feature": r = a·x_anchor + b·x_obs + c l − z (scalar, linear).
class LinearFeature final : public FactorN<1, Vec3, Vec3, Vec1> {
 public:
  LinearFeature(Key anchor, Key obs, Key l, Vec3 a, Vec3 b, double c, double z)
      : FactorN({anchor, obs, l}, NoiseModel::isotropic(1, 0.1)), a_(a), b_(b), c_(c), z_(z) {}
  Residual error(const Vec3& xa, const Vec3& xo, const Vec1& l, Jacobian<Vec3>* Ja, Jacobian<Vec3>* Jo,
                 Jacobian<Vec1>* Jl) const override {
    if (Ja) *Ja = a_.transpose();
    if (Jo) *Jo = b_.transpose();
    if (Jl) (*Jl)(0, 0) = c_;
    return Residual(a_.dot(xa) + b_.dot(xo) + c_ * l(0) - z_);
  }

 private:
  Vec3 a_, b_;
  double c_, z_;
};

TEST(Marginalization, PriorReproducesTheFullSolutionOnALinearGaussianProblem) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  const auto rv = [&] { return Vec3(n(rng), n(rng), n(rng)); };
  const auto rm = [&] { return Eigen::Matrix3d(Eigen::Matrix3d::Identity() + 0.3 * Eigen::Matrix3d::Random()); };
  const int K = 5, L = 12;
  Values x;
  for (int k = 0; k < K; ++k) x.insert(symbol('x', k), Vec3(rv()));
  for (int l = 0; l < L; ++l) x.insert(symbol('l', l), Vec1(n(rng)));
  FactorGraph keep, marg;  // factors that stay / that touch x0 or the features anchored in x0
  marg.emplace<PriorFactor<Vec3>>(symbol('x', 0), rv(), NoiseModel::isotropic(3, 1.0));
  for (int k = 0; k + 1 < K; ++k)
    (k == 0 ? marg : keep).emplace<LinearPair>(symbol('x', k), symbol('x', k + 1), rm(), rm(), rv());
  std::vector<Key> features0;
  for (int l = 0; l < L; ++l) {
    const int anchor = l % 3;  // features 0, 3, 6, 9 are anchored in x0
    if (anchor == 0) features0.push_back(symbol('l', l));
    for (int o = anchor + 1; o < std::min(K, anchor + 4); ++o)
      (anchor == 0 ? marg : keep).emplace<LinearFeature>(symbol('x', anchor), symbol('x', o), symbol('l', l), rv(), rv(),
                                                         1.0 + 0.2 * n(rng), n(rng));
  }
  // Full solution.
  FactorGraph full = keep;
  for (const auto& f : marg) full.add(f);
  Values x_full = x;
  OptimizerOptions o;
  o.algorithm = Algorithm::kGaussNewton;
  o.num_threads = 1;
  ASSERT_TRUE(Optimizer(o).optimize(full, x_full).success());

  // Marginalize features0 then x0 at the initial values (any point: the problem is linear).
  ThreadPool pool(1);
  const MarginalSystem m = marginalize(marg, x, features0, {symbol('x', 0)}, pool);
  ASSERT_EQ(m.kept.size(), 3u);  // x1, x2, x3 (the features anchored in x0 are seen up to x3)
  std::vector<Vec3> x_bar;
  for (Key k : m.kept) x_bar.push_back(x.at<Vec3>(k));
  const auto prior = MarginalizationPrior<Vec3>::from_hessian(m.kept, x_bar, m.H, m.g);
  EXPECT_EQ(prior->residual_dim(), 9);
  FactorGraph reduced = keep;
  reduced.add(prior);
  Values x_red;
  for (int k = 1; k < K; ++k) x_red.insert(symbol('x', k), x.at<Vec3>(symbol('x', k)));
  for (int l = 0; l < L; ++l)
    if (l % 3 != 0) x_red.insert(symbol('l', l), x.at<Vec1>(symbol('l', l)));
  ASSERT_TRUE(Optimizer(o).optimize(reduced, x_red).success());
  for (int k = 1; k < K; ++k)
    EXPECT_LT((x_red.at<Vec3>(symbol('x', k)) - x_full.at<Vec3>(symbol('x', k))).norm(), 1e-8) << "x" << k;
  for (int l = 0; l < L; ++l)
    if (l % 3 != 0) EXPECT_NEAR(x_red.at<Vec1>(symbol('l', l))(0), x_full.at<Vec1>(symbol('l', l))(0), 1e-8);
  // The reduced cost at the solution equals the full cost up to the constant the prior drops.
  EXPECT_GT(full.cost(x_full), 0.0);
}

TEST(Marginalization, PriorJacobiansMatchNumericAtTheLinearizationPoint) {
  std::mt19937 rng(2);
  std::normal_distribution<double> n;
  std::vector<ImuState> xb(2);
  Values v;
  for (int k = 0; k < 2; ++k) {
    ImuState::Tangent d;
    for (int a = 0; a < 15; ++a) d(a) = n(rng);
    xb[k] = ImuState().plus(d);
    v.insert(symbol('x', k), xb[k]);
  }
  const Eigen::MatrixXd A = Eigen::MatrixXd::Random(30, 30);
  const Eigen::MatrixXd H = A * A.transpose();
  const Eigen::VectorXd g = Eigen::VectorXd::Random(30);
  FactorGraph graph;
  graph.add(MarginalizationPrior<ImuState>::from_hessian({symbol('x', 0), symbol('x', 1)}, xb, H, g));
  const JacobianCheckResult r = check_jacobians(graph, v, 1e-6);
  EXPECT_TRUE(r.ok) << r.message();
  // Its cost reproduces the quadratic model: ‖r*‖² + 2g·δ + δᵀHδ − ‖r*‖² at δ.
  const double c0 = graph.cost(v);
  Eigen::VectorXd d = 1e-3 * Eigen::VectorXd::Random(30);
  Values w;
  w.insert(symbol('x', 0), xb[0].plus(d.head<15>()));
  w.insert(symbol('x', 1), xb[1].plus(d.tail<15>()));
  EXPECT_NEAR(graph.cost(w) - c0, 2 * g.dot(d) + d.dot(H * d), 1e-6);
  // Singular or non-finite information is refused.
  EXPECT_THROW(MarginalizationPrior<ImuState>::from_hessian({symbol('x', 0), symbol('x', 1)}, xb,
                                                            Eigen::MatrixXd::Zero(30, 30), g),
               NumericalError);
}

}  // namespace
}  // namespace slamkit
