// SO(3): 3D rotations, stored as a unit quaternion (q and −q are the same rotation).
//
// Tangent: rotation vector φ (axis · angle). Right perturbation R ⊞ δ = R · Exp(δ).
// Jr(φ) = I − (1−cθ)/θ² [φ]× + (θ−sθ)/θ³ [φ]×², Jl(φ) = Jr(−φ) = R(φ) Jr(φ), Ad = R.
// Log uses θ = 2·atan2(‖v‖, |w|), accurate from θ = 0 up to and including θ = π.
// Jacobians: J_out_in = ∂ Log(out⁻¹ · out(in ⊞ δ)) / ∂δ. Value type, thread-safe.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "slamkit/geometry/lie_math.h"

namespace slamkit {

class SO3 {
 public:
  static constexpr int kDim = 3;
  using Tangent = Eigen::Vector3d;
  using Jacobian = Eigen::Matrix3d;

  SO3() = default;
  /// Normalizes q; throws std::invalid_argument if q is zero or not finite.
  explicit SO3(const Eigen::Quaterniond& q);
  static SO3 identity() { return SO3(); }
  /// Nearest rotation to a (nearly) orthonormal matrix.
  static SO3 from_matrix(const Eigen::Matrix3d& R);
  /// R = Rz(yaw) · Ry(pitch) · Rx(roll) (the TORO / GTSAM EDGE3 convention).
  static SO3 from_rpy(double roll, double pitch, double yaw);
  Eigen::Vector3d to_rpy() const;

  const Eigen::Quaterniond& quaternion() const { return q_; }
  Eigen::Matrix3d matrix() const { return q_.toRotationMatrix(); }

  static SO3 exp(const Tangent& phi, Jacobian* J_out_phi = nullptr);
  Tangent log(Jacobian* J_out_this = nullptr) const;

  SO3 compose(const SO3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  SO3 operator*(const SO3& other) const { return compose(other); }
  SO3 inverse(Jacobian* J_out_this = nullptr) const;
  /// this⁻¹ · other
  SO3 between(const SO3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;
  /// R p
  Eigen::Vector3d act(const Eigen::Vector3d& p, Jacobian* J_out_this = nullptr,
                      Eigen::Matrix3d* J_out_p = nullptr) const;
  Jacobian adjoint() const { return matrix(); }

  /// this ⊞ δ = this · Exp(δ)
  SO3 plus(const Tangent& delta, Jacobian* J_out_this = nullptr, Jacobian* J_out_delta = nullptr) const;
  /// this ⊟ other = Log(other⁻¹ · this)
  Tangent minus(const SO3& other, Jacobian* J_out_this = nullptr, Jacobian* J_out_other = nullptr) const;

  static Jacobian right_jacobian(const Tangent& phi);
  static Jacobian left_jacobian(const Tangent& phi) { return right_jacobian(-phi); }
  static Jacobian right_jacobian_inverse(const Tangent& phi);
  static Jacobian left_jacobian_inverse(const Tangent& phi) { return right_jacobian_inverse(-phi); }

 private:
  struct NoNormalize {};
  SO3(const Eigen::Quaterniond& q, NoNormalize) : q_(q) {}
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
};

}  // namespace slamkit
