// Factor: one term ρ(‖R r(x_1..x_k)‖²) of a nonlinear least-squares cost.
//
// evaluate() gives the raw residual r and its Jacobians with respect to tangent
// perturbations of each variable (x_k ⊞ δ_k), column-major residual_dim × tangent_dim(k).
// linearize() applies the noise model (whitening by R, RᵀR = Ω) and the robust kernel with
// Triggs' correction (as in Ceres): with s = ‖r̃‖², r̃ = R r, and ρ', ρ'' at s,
//   α = 1 − sqrt(1 + 2 s ρ''/ρ')   (0 when ρ'' ≤ 0 or s = 0)
//   r̂ = sqrt(ρ')/(1 − α) · r̃,   Ĵ = sqrt(ρ') (I − α r̃ r̃ᵀ / s) J̃
// so that the Gauss-Newton model of ρ around x has gradient Ĵᵀ r̂ and Hessian ĴᵀĴ.
//
// FactorN<R, V...> is the typed way to write a factor: implement
//   Residual error(const V&... values, Jacobian<V>*... J) const
// where each J may be null. Factors are immutable once built; evaluate() is thread-safe.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <tuple>
#include <memory>
#include <utility>
#include <vector>

#include "slamkit/core/key.h"
#include "slamkit/core/manifold.h"
#include "slamkit/core/noise_model.h"
#include "slamkit/core/robust_kernel.h"

namespace slamkit {

class Factor {
 public:
  Factor(std::vector<Key> keys, int residual_dim, std::shared_ptr<const NoiseModel> noise,
         std::shared_ptr<const RobustKernel> kernel = nullptr);
  virtual ~Factor() = default;

  const std::vector<Key>& keys() const { return keys_; }
  int residual_dim() const { return residual_dim_; }
  const NoiseModel* noise_model() const { return noise_.get(); }
  const RobustKernel* robust_kernel() const { return kernel_.get(); }
  void set_robust_kernel(std::shared_ptr<const RobustKernel> kernel) { kernel_ = std::move(kernel); }
  /// The manifold variable k must live on (checked against Values when a problem is built).
  virtual const Manifold& variable_manifold(std::size_t k) const = 0;

  /// Raw residual and Jacobians. `jacobians` may be null, and so may any entry of it.
  /// Returns false if the residual or a Jacobian is not finite.
  virtual bool evaluate(const double* const* params, double* residual, double* const* jacobians) const = 0;

  /// Whitened and robustified residual and Jacobians (see above). Returns ρ(s), the factor's
  /// contribution to the cost, or NaN if evaluation failed. FactorN overrides it with a
  /// fixed-size path (same arithmetic, no dynamic-size loops or per-variable virtual calls).
  virtual double linearize(const double* const* params, double* residual, double* const* jacobians) const;
  /// ρ(s) only (no Jacobians); NaN if evaluation failed.
  double cost(const double* const* params, double* residual_workspace) const;

 protected:
  /// The robust kernel applied to an already whitened residual and Jacobians with s = ‖r̃‖²
  /// (Triggs' correction, above); returns ρ(s). Requires a kernel.
  double robustify(double s, double* residual, double* const* jacobians) const;

 private:
  std::vector<Key> keys_;
  int residual_dim_;
  std::shared_ptr<const NoiseModel> noise_;
  std::shared_ptr<const RobustKernel> kernel_;
};

template <int R, class... Vars>
class FactorN : public Factor {
 public:
  static constexpr int kResidualDim = R;
  static constexpr std::size_t kArity = sizeof...(Vars);
  using Residual = Eigen::Matrix<double, R, 1>;
  template <class V>
  using Jacobian = Eigen::Matrix<double, R, ManifoldTraits<V>::kTangent>;

  FactorN(const std::array<Key, kArity>& keys, std::shared_ptr<const NoiseModel> noise,
          std::shared_ptr<const RobustKernel> kernel = nullptr)
      : Factor(std::vector<Key>(keys.begin(), keys.end()), R, std::move(noise), std::move(kernel)) {}

  /// The residual at typed values; fills each non-null Jacobian.
  virtual Residual error(const Vars&... values, Jacobian<Vars>*... jacobians) const = 0;

  const Manifold& variable_manifold(std::size_t k) const final {
    static const std::array<const Manifold*, kArity> m = {&ManifoldOf<Vars>::instance()...};
    return *m[k];
  }

  bool evaluate(const double* const* params, double* residual, double* const* jacobians) const final {
    return evaluate_impl(params, residual, jacobians, std::index_sequence_for<Vars...>{});
  }

  double linearize(const double* const* params, double* residual, double* const* jacobians) const override {
    return linearize_typed(*this, params, residual, jacobians);
  }

 protected:
  /// Factor::linearize in fixed sizes: error() of `self` (a final class calls it without a
  /// virtual dispatch), whitening by R in R×R / diagonal fixed-size products, residual and
  /// Jacobians written once into the caller's buffers. Same arithmetic as the generic path.
  template <class Self>
  static double linearize_typed(const Self& self, const double* const* params, double* residual,
                                double* const* jacobians) {
    return self.linearize_fixed(self, params, residual, jacobians, std::index_sequence_for<Vars...>{});
  }

 private:
  // M ← R M for a fixed R-row block (the residual or one Jacobian).
  template <class M>
  static void whiten_fixed(const NoiseModel& noise, M& m) {
    const double* w = noise.whitening_data();
    if (noise.kind() == NoiseModel::Kind::kDiagonal) {
      const Eigen::Map<const Eigen::Matrix<double, R, 1>> d(w);
      for (int c = 0; c < M::ColsAtCompileTime; ++c) m.col(c).array() *= d.array();
    } else if (noise.kind() == NoiseModel::Kind::kDense) {
      const Eigen::Map<const Eigen::Matrix<double, R, R>> U(w);
      for (int c = 0; c < M::ColsAtCompileTime; ++c) {
        const Eigen::Matrix<double, R, 1> v = U.lazyProduct(m.col(c));
        m.col(c) = v;
      }
    }
  }

  template <class Self, std::size_t... I>
  double linearize_fixed(const Self& self, const double* const* params, double* residual, double* const* jacobians,
                         std::index_sequence<I...>) const {
    std::tuple<Jacobian<Vars>...> J;
    const bool want = jacobians != nullptr;
    Residual r = self.error(ManifoldTraits<Vars>::from_params(params[I])...,
                                  (want && jacobians[I] ? &std::get<I>(J) : nullptr)...);
    bool finite = r.allFinite();
    if (want) ((jacobians[I] ? (finite = finite && std::get<I>(J).allFinite(), 0) : 0), ...);
    if (!finite) return std::numeric_limits<double>::quiet_NaN();
    const NoiseModel& noise = *noise_model();
    whiten_fixed(noise, r);
    if (want)
      ((jacobians[I] ? (whiten_fixed(noise, std::get<I>(J)), Eigen::Map<Jacobian<Vars>>(jacobians[I]) = std::get<I>(J), 0)
                     : 0),
       ...);
    Eigen::Map<Residual> out(residual);
    out = r;
    double s = 0.0;
    for (int i = 0; i < R; ++i) s += r[i] * r[i];
    return robust_kernel() ? robustify(s, residual, jacobians) : s;
  }

  template <std::size_t... I>
  bool evaluate_impl(const double* const* params, double* residual, double* const* jacobians,
                     std::index_sequence<I...>) const {
    std::tuple<Jacobian<Vars>...> J;
    const Residual r = error(ManifoldTraits<Vars>::from_params(params[I])...,
                             (jacobians && jacobians[I] ? &std::get<I>(J) : nullptr)...);
    Eigen::Map<Residual> out(residual);
    out = r;
    bool finite = r.allFinite();
    if (jacobians) {
      ((jacobians[I] ? (Eigen::Map<Jacobian<Vars>>(jacobians[I]) = std::get<I>(J),
                        finite = finite && std::get<I>(J).allFinite(), 0)
                     : 0),
       ...);
    }
    return finite;
  }
};

}  // namespace slamkit
