// SO(2): planar rotations, stored as an angle wrapped to (−π, π].
//
// Tangent: the scalar angle θ. Right perturbation R ⊞ δ = R · Exp(δ). SO(2) is abelian,
// so Ad = 1 and every Jacobian of compose/between/exp/log is ±1. All functions taking
// Jacobian pointers follow the library convention J_out_in = ∂ Log(out⁻¹·out(in ⊞ δ)) / ∂δ.
// Thread safety: value type, no shared state.
#pragma once

#include <Eigen/Core>

#include "slamkit/geometry/lie_math.h"

namespace slamkit {

class SO2 {
 public:
  static constexpr int kDim = 1;
  using Tangent = Eigen::Matrix<double, 1, 1>;
  using Jacobian = Eigen::Matrix<double, 1, 1>;

  SO2() = default;
  explicit SO2(double angle) : angle_(wrap_angle(angle)) {}
  static SO2 identity() { return SO2(); }
  static SO2 from_matrix(const Eigen::Matrix2d& R);

  double angle() const { return angle_; }
  Eigen::Matrix2d matrix() const;

  static SO2 exp(const Tangent& tau, Jacobian* J_out_tau = nullptr);
  Tangent log(Jacobian* J_out_this = nullptr) const;

  SO2 compose(const SO2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SO2 operator*(const SO2& other) const { return compose(other); }
  SO2 inverse(Jacobian* J_out_this = nullptr) const;
  /// this⁻¹ · other
  SO2 between(const SO2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  /// R · p, with J_out_this (2×1) for the rotation and J_out_p (2×2).
  Eigen::Vector2d act(const Eigen::Vector2d& p, Eigen::Matrix<double, 2, 1>* J_out_this = nullptr,
                      Eigen::Matrix2d* J_out_p = nullptr) const;
  Jacobian adjoint() const { return Jacobian::Identity(); }

  /// this ⊞ δ = this · Exp(δ)
  SO2 plus(const Tangent& delta, Jacobian* J_out_this = nullptr, Jacobian* J_out_delta = nullptr) const;
  /// this ⊟ other = Log(other⁻¹ · this)
  Tangent minus(const SO2& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;

  static Jacobian right_jacobian(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian left_jacobian(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian right_jacobian_inverse(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian left_jacobian_inverse(const Tangent&) { return Jacobian::Identity(); }

 private:
  double angle_ = 0.0;
};

}  // namespace slamkit
