// MarginalizationPrior<T>: the linear prior a marginalization leaves on the kept variables.
//
// Marginalizing variables m out of the Gauss-Newton model ‖r + J δ‖² (H = JᵀJ, g = Jᵀr) by the
// Schur complement (linear/schur_complement.h) gives, on the kept variables k,
//   H* = H_kk − H_km H_mm⁻¹ H_mk,   g* = g_k − H_km H_mm⁻¹ g_m,
// i.e. the quadratic cost δᵀH*δ + 2 g*ᵀδ + const around the linearization point x̄. With the
// eigen-decomposition H* = V Λ Vᵀ (eigenvalues below eps·λ_max dropped: the unobservable
// directions, yaw and position for VIO), J* = Λ^{1/2} Vᵀ and r* = Λ^{-1/2} Vᵀ g* give
//   cost = ‖r* + J* (x ⊟ x̄)‖²  (up to a constant),   residual dim = rank(H*).
// First-estimate Jacobians: the Jacobian w.r.t. each variable is the block of J*, fixed at x̄
// (it equals the exact derivative at x̄; elsewhere it deliberately ignores the Jr⁻¹ factor of
// the rotation's ⊟), so the prior never adds information along directions it did not have.
// T: any type with ManifoldTraits and minus() (Lie groups, ImuState) or an Eigen vector.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "slamkit/core/error.h"
#include "slamkit/core/factor.h"

namespace slamkit {

template <class T>
class MarginalizationPrior final : public Factor {
 public:
  static constexpr int kDim = ManifoldTraits<T>::kTangent;

  /// keys[k] at linearization point x_bar[k]; H (n·kDim square), g (n·kDim) in keys' order.
  /// Throws NumericalError if H is not finite or has no eigenvalue above eps·λ_max.
  static std::shared_ptr<MarginalizationPrior> from_hessian(std::vector<Key> keys, std::vector<T> x_bar,
                                                            const Eigen::MatrixXd& H, const Eigen::VectorXd& g,
                                                            double eps = 1e-8) {
    const int n = static_cast<int>(keys.size()) * kDim;
    if (H.rows() != n || H.cols() != n || g.size() != n || x_bar.size() != keys.size())
      throw std::invalid_argument("MarginalizationPrior: sizes do not match the keys");
    if (!H.allFinite() || !g.allFinite()) throw NumericalError("MarginalizationPrior: H or g is not finite");
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (H + H.transpose()));
    const Eigen::VectorXd& l = es.eigenvalues();
    const double lmax = l.maxCoeff();
    if (!(lmax > 0.0)) throw NumericalError("MarginalizationPrior: the marginal information is zero");
    std::vector<int> kept;
    for (int i = 0; i < n; ++i)
      if (l(i) > eps * lmax) kept.push_back(i);
    Eigen::MatrixXd J(kept.size(), n);
    Eigen::VectorXd r0(kept.size());
    for (std::size_t a = 0; a < kept.size(); ++a) {
      const double s = std::sqrt(l(kept[a]));
      J.row(a) = s * es.eigenvectors().col(kept[a]).transpose();
      r0(a) = es.eigenvectors().col(kept[a]).dot(g) / s;
    }
    return std::shared_ptr<MarginalizationPrior>(new MarginalizationPrior(std::move(keys), std::move(x_bar), J, r0));
  }

  const Manifold& variable_manifold(std::size_t) const override { return ManifoldOf<T>::instance(); }
  const std::vector<T>& linearization_point() const { return x_bar_; }
  const Eigen::MatrixXd& jacobian() const { return J_; }
  const Eigen::VectorXd& residual_at_linearization() const { return r0_; }

  bool evaluate(const double* const* params, double* residual, double* const* jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residual, r0_.size());
    r = r0_;
    for (std::size_t k = 0; k < x_bar_.size(); ++k) {
      const T x = ManifoldTraits<T>::from_params(params[k]);
      Eigen::Matrix<double, kDim, 1> d;
      if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>) d = x - x_bar_[k];
      else d = x.minus(x_bar_[k]);
      r += J_.middleCols<kDim>(kDim * k) * d;
      if (jacobians && jacobians[k])
        Eigen::Map<Eigen::MatrixXd>(jacobians[k], r0_.size(), kDim) = J_.middleCols<kDim>(kDim * k);
    }
    return r.allFinite();
  }

 private:
  MarginalizationPrior(std::vector<Key> keys, std::vector<T> x_bar, Eigen::MatrixXd J, Eigen::VectorXd r0)
      : Factor(std::move(keys), static_cast<int>(r0.size()), NoiseModel::unit(static_cast<int>(r0.size()))),
        x_bar_(std::move(x_bar)),
        J_(std::move(J)),
        r0_(std::move(r0)) {}
  std::vector<T> x_bar_;
  Eigen::MatrixXd J_;
  Eigen::VectorXd r0_;
};

}  // namespace slamkit
