// PriorFactor<T>: a unary factor pulling a variable towards a measured value z.
//   Lie groups: e = x ⊟ z = Log(z⁻¹ x), J = Jr⁻¹(e).   Vectors: e = x − z, J = I.
#pragma once

#include "slamkit/core/factor.h"

namespace slamkit {

template <class T>
class PriorFactor final : public FactorN<ManifoldTraits<T>::kTangent, T> {
  using Base = FactorN<ManifoldTraits<T>::kTangent, T>;

 public:
  PriorFactor(Key key, const T& measured, std::shared_ptr<const NoiseModel> noise,
              std::shared_ptr<const RobustKernel> kernel = nullptr)
      : Base({key}, std::move(noise), std::move(kernel)), measured_(measured) {}

  typename Base::Residual error(const T& x, typename Base::template Jacobian<T>* J) const override {
    if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>) {
      if (J) J->setIdentity();
      return x - measured_;
    } else {
      typename T::Jacobian J_x;
      const typename T::Tangent e = x.minus(measured_, J ? &J_x : nullptr);
      if (J) *J = J_x;
      return e;
    }
  }
  const T& measured() const { return measured_; }

 private:
  T measured_;
};

}  // namespace slamkit
