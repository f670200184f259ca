// ImuState: the navigation state of a visual-inertial keyframe as ONE manifold variable,
//   rotation R = R_world_imu (SO3), position p and velocity v of the IMU in the world frame,
//   gyroscope bias b_g and accelerometer bias b_a (IMU frame).
//   parameters (ambient, 16): [qx, qy, qz, qw, p(3), v(3), b_g(3), b_a(3)]
//   tangent (15):             [δφ, δv, δp, δb_g, δb_a]  (the preintegration's error order)
//   R ⊞ δφ = R · Exp(δφ); p, v, b_g, b_a additive.
// Why one 15-dof variable rather than GTSAM's separate pose / velocity / bias keys: the
// window's marginalization eliminates a keyframe through linear/schur_complement, which
// eliminates non-adjacent blocks; one block per keyframe keeps "remove keyframe k" a single
// block, the IMU factor binary and the prior's bookkeeping per keyframe. The cost is a few
// zero columns in the reprojection Jacobians (they touch only R and p).
#pragma once

#include <Eigen/Core>

#include "slamkit/core/manifold.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

struct ImuState {
  static constexpr int kDim = 15;
  using Tangent = Eigen::Matrix<double, 15, 1>;
  using Jacobian = Eigen::Matrix<double, 15, 15>;

  SO3 R;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();
  Eigen::Vector3d ba = Eigen::Vector3d::Zero();

  SE3 pose() const { return SE3(R, p); }

  ImuState plus(const Tangent& d) const {
    ImuState s;
    s.R = R.plus(d.segment<3>(0));
    s.v = v + d.segment<3>(3);
    s.p = p + d.segment<3>(6);
    s.bg = bg + d.segment<3>(9);
    s.ba = ba + d.segment<3>(12);
    return s;
  }
  /// this ⊟ other, so that other ⊞ (this ⊟ other) = this. J_out_this (if given) is
  /// ∂(this ⊞ δ ⊟ other)/∂δ = diag(Jr⁻¹(φ), I, I, I, I).
  Tangent minus(const ImuState& other, Jacobian* J_out_this = nullptr) const {
    Tangent d;
    SO3::Jacobian Jr_inv;
    d.segment<3>(0) = R.minus(other.R, J_out_this ? &Jr_inv : nullptr);
    d.segment<3>(3) = v - other.v;
    d.segment<3>(6) = p - other.p;
    d.segment<3>(9) = bg - other.bg;
    d.segment<3>(12) = ba - other.ba;
    if (J_out_this) {
      J_out_this->setIdentity();
      J_out_this->block<3, 3>(0, 0) = Jr_inv;
    }
    return d;
  }
};

template <>
struct ManifoldTraits<ImuState> {
  static constexpr int kAmbient = 16, kTangent = 15;
  static const char* name() { return "ImuState"; }
  static void to_params(const ImuState& x, double* p) {
    Eigen::Map<Eigen::Vector4d> q(p);
    q = x.R.quaternion().coeffs();
    Eigen::Map<Eigen::Matrix<double, 12, 1>> rest(p + 4);
    rest << x.p, x.v, x.bg, x.ba;
  }
  static ImuState from_params(const double* p) {
    ImuState x;
    x.R = SO3(Eigen::Quaterniond(Eigen::Map<const Eigen::Vector4d>(p)));
    x.p = Eigen::Map<const Eigen::Vector3d>(p + 4);
    x.v = Eigen::Map<const Eigen::Vector3d>(p + 7);
    x.bg = Eigen::Map<const Eigen::Vector3d>(p + 10);
    x.ba = Eigen::Map<const Eigen::Vector3d>(p + 13);
    return x;
  }
};

}  // namespace slamkit
