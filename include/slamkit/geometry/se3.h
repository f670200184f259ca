// SE(3): rigid motions T = (R, t), acting as p ↦ R p + t.
//
// Tangent order τ = [ρ; φ] (translation first, matching g2o's information layout).
// Right perturbation T ⊞ δ = T · Exp(δ). Exp(ρ, φ) = (Exp(φ), Jl(φ) ρ).
// Jl(τ) = [[Jl(φ), Q(ρ, φ)], [0, Jl(φ)]] (Barfoot, eq. 7.86), Jr(τ) = Jl(−τ),
// Ad = [[R, [t]× R], [0, R]]. Jacobians: J_out_in = ∂ Log(out⁻¹ · out(in ⊞ δ)) / ∂δ.
// Value type, thread-safe.
#pragma once

#include <Eigen/Core>

#include "slamkit/geometry/so3.h"

namespace slamkit {

class SE3 {
 public:
  static constexpr int kDim = 6;
  using Tangent = Eigen::Matrix<double, 6, 1>;
  using Jacobian = Eigen::Matrix<double, 6, 6>;

  SE3() = default;
  SE3(const SO3& R, const Eigen::Vector3d& t) : R_(R), t_(t) {}
  SE3(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) : R_(q), t_(t) {}
  static SE3 identity() { return SE3(); }
  /// From a 4×4 or 3×4 [R | t] matrix; R is projected to the nearest rotation.
  static SE3 from_matrix(const Eigen::Matrix<double, 3, 4>& T);

  const SO3& rotation() const { return R_; }
  const Eigen::Vector3d& translation() const { return t_; }
  Eigen::Matrix4d matrix() const;

  static SE3 exp(const Tangent& tau, Jacobian* J_out_tau = nullptr);
  Tangent log(Jacobian* J_out_this = nullptr) const;

  SE3 compose(const SE3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SE3 operator*(const SE3& other) const { return compose(other); }
  SE3 inverse(Jacobian* J_out_this = nullptr) const;
  /// this⁻¹ · other
  SE3 between(const SE3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  /// R p + t
  Eigen::Vector3d act(const Eigen::Vector3d& p, Eigen::Matrix<double, 3, 6>* J_out_this = nullptr,
                      Eigen::Matrix3d* J_out_p = nullptr) const;
  Jacobian adjoint() const;

  /// this ⊞ δ = this · Exp(δ)
  SE3 plus(const Tangent& delta, Jacobian* J_out_this = nullptr, Jacobian* J_out_delta = nullptr) const;
  /// this ⊟ other = Log(other⁻¹ · this)
  Tangent minus(const SE3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;

  static Jacobian right_jacobian(const Tangent& tau);
  static Jacobian left_jacobian(const Tangent& tau) { return right_jacobian(-tau); }
  static Jacobian right_jacobian_inverse(const Tangent& tau);
  static Jacobian left_jacobian_inverse(const Tangent& tau) { return right_jacobian_inverse(-tau); }

 private:
  SO3 R_;
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();
};

}  // namespace slamkit
