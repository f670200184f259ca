// SE(2): planar rigid motions T = (R, t), acting as p ↦ R p + t.
//
// Tangent order τ = [ρx, ρy, θ] (translation first, as in g2o files). Right perturbation
// T ⊞ δ = T · Exp(δ). Exp(ρ, θ) = (V(θ) ρ, θ) with V = [[sθ/θ, −(1−cθ)/θ], [(1−cθ)/θ, sθ/θ]].
// Jacobians: J_out_in = ∂ Log(out⁻¹ · out(in ⊞ δ)) / ∂δ; Jl(τ) = Jr(−τ); Ad = [[R, (t_y, −t_x)ᵀ], [0, 1]].
// Thread safety: value type, no shared state.
#pragma once

#include <Eigen/Core>

#include "slamkit/geometry/so2.h"

namespace slamkit {

class SE2 {
 public:
  static constexpr int kDim = 3;
  using Tangent = Eigen::Vector3d;
  using Jacobian = Eigen::Matrix3d;

  SE2() = default;
  SE2(const SO2& R, const Eigen::Vector2d& t) : R_(R), t_(t) {}
  SE2(double x, double y, double theta) : R_(theta), t_(x, y) {}
  static SE2 identity() { return SE2(); }

  const SO2& rotation() const { return R_; }
  const Eigen::Vector2d& translation() const { return t_; }
  double x() const { return t_.x(); }
  double y() const { return t_.y(); }
  double theta() const { return R_.angle(); }
  Eigen::Matrix3d matrix() const;

  static SE2 exp(const Tangent& tau, Jacobian* J_out_tau = nullptr);
  Tangent log(Jacobian* J_out_this = nullptr) const;

  SE2 compose(const SE2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SE2 operator*(const SE2& other) const { return compose(other); }
  SE2 inverse(Jacobian* J_out_this = nullptr) const;
  /// this⁻¹ · other
  SE2 between(const SE2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  /// R p + t
  Eigen::Vector2d act(const Eigen::Vector2d& p, Eigen::Matrix<double, 2, 3>* J_out_this = nullptr,
                      Eigen::Matrix2d* J_out_p = nullptr) const;
  Jacobian adjoint() const;

  /// this ⊞ δ = this · Exp(δ)
  SE2 plus(const Tangent& delta, Jacobian* J_out_this = nullptr, Jacobian* J_out_delta = nullptr) const;
  /// this ⊟ other = Log(other⁻¹ · this)
  Tangent minus(const SE2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;

  static Jacobian right_jacobian(const Tangent& tau);
  static Jacobian left_jacobian(const Tangent& tau) { return right_jacobian(-tau); }
  static Jacobian right_jacobian_inverse(const Tangent& tau);
  static Jacobian left_jacobian_inverse(const Tangent& tau) { return right_jacobian_inverse(-tau); }

 private:
  SO2 R_;
  Eigen::Vector2d t_ = Eigen::Vector2d::Zero();
};

}  // namespace slamkit
