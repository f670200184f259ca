// Property and Jacobian suites shared by SO2, SE2, SO3, SE3 (typed tests). Samples include
// random elements, angles near 0 and near π, and large translations.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"
#include "testing/numeric_jacobian.h"

namespace slamkit {
namespace {

using testing::check_jacobian;
using testing::jacobians_match;
using testing::numeric_jacobian;

// Angles that stress the closed forms: Taylor cutoffs, near 0, near π.
const std::vector<double> kHardAngles = {0.0,  1e-12, 1e-9, 1e-7, 9.9e-5, 1.01e-4, 0.49, 0.51,
                                         0.99, 1.01,  2.0,  3.0,  kPi - 1e-3};

template <class G>
struct Sampler;

template <>
struct Sampler<SO2> {
  static constexpr int kTranslationDim = 0;
  static double angle(const SO2::Tangent& t) { return std::abs(t(0)); }
  static SO2::Tangent tangent(double angle, std::mt19937& rng) {
    return SO2::Tangent(std::bernoulli_distribution(0.5)(rng) ? angle : -angle);
  }
  static Eigen::Vector2d point(std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 3.0);
    return Eigen::Vector2d(n(rng), n(rng));
  }
};
template <>
struct Sampler<SE2> {
  static constexpr int kTranslationDim = 2;
  static double angle(const SE2::Tangent& t) { return std::abs(t(2)); }
  static SE2::Tangent tangent(double angle, std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 2.0);
    return SE2::Tangent(n(rng), n(rng), std::bernoulli_distribution(0.5)(rng) ? angle : -angle);
  }
  static Eigen::Vector2d point(std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 3.0);
    return Eigen::Vector2d(n(rng), n(rng));
  }
};
template <>
struct Sampler<SO3> {
  static constexpr int kTranslationDim = 0;
  static double angle(const SO3::Tangent& t) { return t.norm(); }
  static Eigen::Vector3d axis(std::mt19937& rng) {
    std::normal_distribution<double> n;
    return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  }
  static SO3::Tangent tangent(double angle, std::mt19937& rng) { return axis(rng) * angle; }
  static Eigen::Vector3d point(std::mt19937& rng) { return axis(rng) * 2.5; }
};
template <>
struct Sampler<SE3> {
  static constexpr int kTranslationDim = 3;
  static double angle(const SE3::Tangent& t) { return t.tail<3>().norm(); }
  static SE3::Tangent tangent(double angle, std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 2.0);
    SE3::Tangent t;
    t << n(rng), n(rng), n(rng), Sampler<SO3>::tangent(angle, rng);
    return t;
  }
  static Eigen::Vector3d point(std::mt19937& rng) { return Sampler<SO3>::axis(rng) * 2.5; }
};

template <class G>
Eigen::MatrixXd group_matrix(const G& g) {
  return g.matrix();
}

template <class G>
::testing::AssertionResult same_element(const G& a, const G& b, double tol, double scale = 1.0) {
  const double err = (group_matrix(a) - group_matrix(b)).template lpNorm<Eigen::Infinity>();
  scale = std::max({scale, group_matrix(a).template lpNorm<Eigen::Infinity>(),
                    group_matrix(b).template lpNorm<Eigen::Infinity>()});
  if (err <= tol * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "elements differ by " << err << "\n"
                                       << group_matrix(a) << "\nvs\n"
                                       << group_matrix(b);
}

template <class G>
class LieGroupTest : public ::testing::Test {
 protected:
  using T = typename G::Tangent;
  // Tangent samples whose rotation angle is in [0, π): log(exp(τ)) = τ holds for these.
  std::vector<T> tangents() {
    std::mt19937 rng(42);
    std::vector<T> out;
    for (double a : kHardAngles) out.push_back(Sampler<G>::tangent(a, rng));
    std::uniform_real_distribution<double> u(0.0, kPi - 1e-3);
    for (int i = 0; i < 40; ++i) out.push_back(Sampler<G>::tangent(u(rng), rng));
    return out;
  }
  // Group elements, including large translations (for SE groups) and angles within 1e-9 of π.
  std::vector<G> elements() {
    std::vector<G> out;
    for (const T& t : tangents()) out.push_back(G::exp(t));
    std::mt19937 rng(7);
    for (double scale : {1e3, 1e5}) {
      T t = Sampler<G>::tangent(1.0, rng);
      if constexpr (Sampler<G>::kTranslationDim > 0) t.head(Sampler<G>::kTranslationDim) *= scale;
      out.push_back(G::exp(t));
    }
    return out;
  }
};

using Groups = ::testing::Types<SO2, SE2, SO3, SE3>;
TYPED_TEST_SUITE(LieGroupTest, Groups);

TYPED_TEST(LieGroupTest, ExpLogRoundTrip) {
  using G = TypeParam;
  for (const auto& tau : this->tangents()) {
    const typename G::Tangent back = G::exp(tau).log();
    EXPECT_LT((back - tau).template lpNorm<Eigen::Infinity>(), 1e-12 * std::max(1.0, tau.norm()))
        << "tau " << tau.transpose() << " back " << back.transpose();
  }
  for (const auto& x : this->elements()) EXPECT_TRUE(same_element(G::exp(x.log()), x, 1e-12));
}

TYPED_TEST(LieGroupTest, NearPiIsFiniteAndAccurate) {
  using G = TypeParam;
  std::mt19937 rng(3);
  for (double eps : {0.0, 1e-15, 1e-12, 1e-9, 1e-6}) {
    const auto tau = Sampler<G>::tangent(kPi - eps, rng);
    const G x = G::exp(tau);
    const auto back = x.log();
    ASSERT_TRUE(back.allFinite()) << back.transpose();
    EXPECT_TRUE(same_element(G::exp(back), x, 1e-12));
    EXPECT_TRUE(G::right_jacobian(back).allFinite());
    EXPECT_TRUE(G::right_jacobian_inverse(back).allFinite());
    const Eigen::MatrixXd I = G::right_jacobian(back) * G::right_jacobian_inverse(back);
    EXPECT_LT((I - Eigen::MatrixXd::Identity(G::kDim, G::kDim)).norm(), 1e-9);
  }
}

TYPED_TEST(LieGroupTest, PlusMinusRoundTrip) {
  using G = TypeParam;
  const auto xs = this->elements();
  for (size_t i = 0; i < xs.size(); ++i) {
    const G& x = xs[i];
    const G& y = xs[(i * 7 + 3) % xs.size()];
    EXPECT_TRUE(same_element(x.plus(y.minus(x)), y, 1e-9));  // x ⊞ (y ⊟ x) = y
  }
}

TYPED_TEST(LieGroupTest, GroupAxioms) {
  using G = TypeParam;
  const auto xs = this->elements();
  for (size_t i = 0; i < xs.size(); ++i) {
    const G& a = xs[i];
    const G& b = xs[(i + 5) % xs.size()];
    const G& c = xs[(i + 11) % xs.size()];
    const double scale = a.matrix().template lpNorm<Eigen::Infinity>();  // rounding grows with ‖t‖
    EXPECT_TRUE(same_element(a * a.inverse(), G::identity(), 1e-12, scale));
    EXPECT_TRUE(same_element((a * b) * c, a * (b * c), 1e-12));
    EXPECT_TRUE(same_element(a.between(b), a.inverse() * b, 1e-12));
  }
}

TYPED_TEST(LieGroupTest, AdjointIdentities) {
  using G = TypeParam;
  const auto xs = this->elements();
  const auto ts = this->tangents();
  for (size_t i = 0; i < xs.size(); ++i) {
    const G& x = xs[i];
    const auto tau = ts[i % ts.size()] * 0.3;
    // x · Exp(τ) · x⁻¹ = Exp(Ad_x τ)
    EXPECT_TRUE(same_element(x * G::exp(tau) * x.inverse(), G::exp(x.adjoint() * tau), 1e-9));
    // Ad(x y) = Ad(x) Ad(y), Ad(x⁻¹) = Ad(x)⁻¹
    const G& y = xs[(i + 3) % xs.size()];
    EXPECT_LT(((x * y).adjoint() - x.adjoint() * y.adjoint()).norm(),
              1e-9 * std::max(1.0, (x * y).adjoint().norm()));
    EXPECT_LT((x.inverse().adjoint() * x.adjoint() - Eigen::MatrixXd::Identity(G::kDim, G::kDim)).norm(),
              1e-9 * std::max(1.0, x.adjoint().squaredNorm()));
  }
}

TYPED_TEST(LieGroupTest, JacobianIdentities) {
  using G = TypeParam;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(G::kDim, G::kDim);
  for (const auto& tau : this->tangents()) {
    EXPECT_LT((G::right_jacobian(tau) - G::left_jacobian(-tau)).norm(), 1e-14);
    EXPECT_LT((G::right_jacobian(tau) * G::right_jacobian_inverse(tau) - I).norm(), 1e-10)
        << tau.transpose();
    EXPECT_LT((G::left_jacobian(tau) * G::left_jacobian_inverse(tau) - I).norm(), 1e-10);
    // Jl = Ad(Exp τ) Jr
    EXPECT_LT((G::left_jacobian(tau) - G::exp(tau).adjoint() * G::right_jacobian(tau)).norm(), 1e-10);
  }
}

TYPED_TEST(LieGroupTest, JacobiansMatchNumeric) {
  using G = TypeParam;
  using J = typename G::Jacobian;
  using T = typename G::Tangent;
  const auto xs = this->elements();
  for (size_t i = 0; i < xs.size(); ++i) {
    const G& a = xs[i];
    const G& b = xs[(i + 4) % xs.size()];
    // Large translations lose digits in the finite differences themselves.
    const double scale = std::max({1.0, a.matrix().template lpNorm<Eigen::Infinity>(),
                                   b.matrix().template lpNorm<Eigen::Infinity>()});
    const double tol = 1e-6 * scale, h = 1e-6;
    SCOPED_TRACE(::testing::Message() << "sample " << i);
    J Ja, Jb;
    a.compose(b, &Ja, &Jb);
    EXPECT_TRUE(check_jacobian<G>([&](const G& x) { return x * b; }, a, Ja, tol, "compose/this", h));
    EXPECT_TRUE(check_jacobian<G>([&](const G& x) { return a * x; }, b, Jb, tol, "compose/other", h));
    a.between(b, &Ja, &Jb);
    EXPECT_TRUE(check_jacobian<G>([&](const G& x) { return x.between(b); }, a, Ja, tol, "between/this", h));
    EXPECT_TRUE(check_jacobian<G>([&](const G& x) { return a.between(x); }, b, Jb, tol, "between/other", h));
    a.inverse(&Ja);
    EXPECT_TRUE(check_jacobian<G>([&](const G& x) { return x.inverse(); }, a, Ja, tol, "inverse", h));

    // minus and plus (y ⊟ x = Log(x⁻¹ y) as a plain vector output).
    b.minus(a, &Jb, &Ja);
    const T d0 = b.minus(a);
    const auto minus_wrt = [&](bool wrt_a) {
      return numeric_jacobian(
          [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
            const T dd(d);
            return wrt_a ? T(b.minus(a.plus(dd)) - d0) : T(b.plus(dd).minus(a) - d0);
          },
          G::kDim, h);
    };
    // minus is continuous only while ‖y ⊟ x‖ stays clear of π.
    if (Sampler<G>::angle(d0) < kPi - 1e-3) {
      EXPECT_TRUE(jacobians_match(Jb, minus_wrt(false), tol, "minus/this"));
      EXPECT_TRUE(jacobians_match(Ja, minus_wrt(true), tol, "minus/other"));
    }
    const T delta = b.log() * 0.25;
    a.plus(delta, &Ja, &Jb);
    EXPECT_TRUE(check_jacobian<G>([&](const G& x) { return x.plus(delta); }, a, Ja, tol, "plus/this", h));
    const J Jdelta = Jb;
    EXPECT_TRUE(jacobians_match(
        Jdelta,
        numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return a.plus(delta + T(d)).minus(a.plus(delta)); },
                         G::kDim, h),
        tol, "plus/delta"));
  }
}

TYPED_TEST(LieGroupTest, ExpLogJacobiansMatchNumeric) {
  using G = TypeParam;
  using T = typename G::Tangent;
  for (const auto& tau : this->tangents()) {
    SCOPED_TRACE(::testing::Message() << "tau " << tau.transpose());
    typename G::Jacobian J;
    const G x = G::exp(tau, &J);
    const auto g_exp = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return G::exp(tau + T(d)).minus(x); };
    EXPECT_TRUE(jacobians_match(J, numeric_jacobian(g_exp, G::kDim), 1e-7, "exp (Jr)"));
    const auto g_expl = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return (G::exp(tau + T(d)) * x.inverse()).log();
    };
    EXPECT_TRUE(jacobians_match(G::left_jacobian(tau), numeric_jacobian(g_expl, G::kDim), 1e-7, "Jl"));
    x.log(&J);
    const auto g_log = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
      return x.plus(T(d)).log() - x.log();
    };
    EXPECT_TRUE(jacobians_match(J, numeric_jacobian(g_log, G::kDim), 1e-6, "log (Jr^-1)"));
  }
}

TYPED_TEST(LieGroupTest, ActJacobiansMatchNumeric) {
  using G = TypeParam;
  using T = typename G::Tangent;
  std::mt19937 rng(11);
  for (const auto& x : this->elements()) {
    const auto p = Sampler<G>::point(rng);
    using P = std::decay_t<decltype(p)>;
    Eigen::Matrix<double, P::RowsAtCompileTime, G::kDim> Jx;
    Eigen::Matrix<double, P::RowsAtCompileTime, P::RowsAtCompileTime> Jp;
    const P y = x.act(p, &Jx, &Jp);
    const double scale = std::max(1.0, x.matrix().template lpNorm<Eigen::Infinity>());
    EXPECT_TRUE(jacobians_match(
        Jx,
        numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return x.plus(T(d)).act(p) - y; },
                         G::kDim),
        1e-6 * scale, "act/this"));
    EXPECT_TRUE(jacobians_match(
        Jp, numeric_jacobian([&](const Eigen::VectorXd& d) -> Eigen::VectorXd { return x.act(p + P(d)) - y; }, p.size()),
        1e-6 * scale, "act/point"));
  }
}

}  // namespace
}  // namespace slamkit
