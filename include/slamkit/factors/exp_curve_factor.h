// The textbook curve-fitting problem as a factor: one sample (x, y) of y = exp(a x² + b x + c) + w,
// w ~ N(0, σ²), on the variable θ = (a, b, c):
//   r(θ) = (y − exp(a x² + b x + c)) / σ,   ∂r/∂θ = −exp(·) (x², x, 1) / σ.
#pragma once

#include <cmath>

#include "slamkit/core/factor.h"

namespace slamkit {

class ExpCurveFactor final : public FactorN<1, Eigen::Vector3d> {
 public:
  ExpCurveFactor(Key theta, double x, double y, double sigma = 1.0,
                 std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({theta}, NoiseModel::isotropic(1, sigma), std::move(kernel)), x_(x), y_(y) {}
  Residual error(const Eigen::Vector3d& t, Jacobian<Eigen::Vector3d>* J) const override {
    const double e = std::exp(t[0] * x_ * x_ + t[1] * x_ + t[2]);
    if (J) *J << -e * x_ * x_, -e * x_, -e;
    return Residual(y_ - e);
  }

 private:
  double x_, y_;
};

}  // namespace slamkit
