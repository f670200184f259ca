#include "slamkit/core/factor.h"

#include <cmath>
#include <limits>

#include "slamkit/core/error.h"

namespace slamkit {

Factor::Factor(std::vector<Key> keys, int residual_dim, std::shared_ptr<const NoiseModel> noise,
               std::shared_ptr<const RobustKernel> kernel)
    : keys_(std::move(keys)), residual_dim_(residual_dim), noise_(std::move(noise)), kernel_(std::move(kernel)) {
  if (!noise_) noise_ = NoiseModel::unit(residual_dim_);
  if (noise_->dim() != residual_dim_)
    throw InputError("", 0, "noise", "noise model dimension " + std::to_string(noise_->dim()) +
                                         " does not match residual dimension " + std::to_string(residual_dim_));
}

double Factor::cost(const double* const* params, double* residual) const {
  if (!evaluate(params, residual, nullptr)) return std::numeric_limits<double>::quiet_NaN();
  noise_->whiten(residual);
  double s = 0.0;
  for (int i = 0; i < residual_dim_; ++i) s += residual[i] * residual[i];
  if (!kernel_) return s;
  double rho[3];
  kernel_->evaluate(s, rho);
  return rho[0];
}

double Factor::linearize(const double* const* params, double* residual, double* const* jacobians) const {
  if (!evaluate(params, residual, jacobians)) return std::numeric_limits<double>::quiet_NaN();
  const int n = residual_dim_;
  const std::size_t k = keys_.size();
  noise_->whiten(residual);
  for (std::size_t v = 0; v < k; ++v)
    if (jacobians && jacobians[v]) noise_->whiten_jacobian(jacobians[v], variable_manifold(v).tangent_dim());
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += residual[i] * residual[i];
  return kernel_ ? robustify(s, residual, jacobians) : s;
}

double Factor::robustify(double s, double* residual, double* const* jacobians) const {
  const int n = residual_dim_;
  const std::size_t k = keys_.size();
  double rho[3];
  kernel_->evaluate(s, rho);
  if (!(rho[1] > 0.0) || s == 0.0) {
    // Flat part of a redescending kernel: the factor exerts no force.
    const double scale = rho[1] > 0.0 ? std::sqrt(rho[1]) : 0.0;
    for (int i = 0; i < n; ++i) residual[i] *= scale;
    for (std::size_t v = 0; v < k; ++v)
      if (jacobians && jacobians[v])
        for (int i = 0, m = n * variable_manifold(v).tangent_dim(); i < m; ++i) jacobians[v][i] *= scale;
    return rho[0];
  }
  const double sqrt_rho1 = std::sqrt(rho[1]);
  double alpha = 0.0;
  if (rho[2] > 0.0) alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
  // Ceres clamps D = 1 + 2sρ''/ρ' > 0 likewise; ρ'' ≤ 0 (all convex-to-concave kernels) ⇒ α = 0.
  const double alpha_over_s = alpha / s;
  if (jacobians) {
    for (std::size_t v = 0; v < k; ++v) {
      if (!jacobians[v]) continue;
      Eigen::Map<Eigen::MatrixXd> J(jacobians[v], n, variable_manifold(v).tangent_dim());
      Eigen::Map<const Eigen::VectorXd> r(residual, n);
      if (alpha != 0.0) J -= alpha_over_s * r * (r.transpose() * J);
      J *= sqrt_rho1;
    }
  }
  const double residual_scale = sqrt_rho1 / (1.0 - alpha);
  for (int i = 0; i < n; ++i) residual[i] *= residual_scale;
  return rho[0];
}

}  // namespace slamkit
