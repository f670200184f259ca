// Least-squares alignment of two registered point sets (Umeyama, IEEE PAMI 13(4), 1991).
//
// Given src points x_i and dst points y_i (columns of 3×N matrices), find the similarity
// y ≈ s R x + t minimizing Σ ‖y_i − (s R x_i + t)‖²:
//   μx, μy the means, σx² = (1/N) Σ ‖x_i − μx‖² (eq. 36), Σxy = (1/N) Σ (y_i − μy)(x_i − μx)ᵀ
//   (eq. 38), Σxy = U D Vᵀ, S = diag(1, 1, det(U)det(V) < 0 ? −1 : 1) (eq. 43),
//   R = U S Vᵀ (eq. 40), s = tr(D S) / σx² (eq. 42; s = 1 without scale), t = μy − s R μx (eq. 41).
// umeyama_yaw() is the 4-DoF variant for visual-inertial odometry, where gravity makes roll
// and pitch observable: R = Rz(θ) about the z axis, no scale; with centred points
//   θ = atan2(Σ (y_y x_x − y_x x_y), Σ (y_x x_x + y_y x_y)).
// Degenerate input (fewer than 3 points, collinear points for the full variants, no
// horizontal spread for the yaw variant) throws std::invalid_argument. Pure functions.
#pragma once

#include <Eigen/Core>

#include "slamkit/geometry/se3.h"

namespace slamkit {

/// A similarity transform p ↦ s R p + t (a rigid motion when s = 1).
struct Similarity3 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
  /// [[s R, t], [0, 1]]
  Eigen::Matrix4d matrix() const {
    Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
    T.topLeftCorner<3, 3>() = scale * R;
    T.topRightCorner<3, 1>() = t;
    return T;
  }
  /// p ↦ (1/s) Rᵀ (p − t)
  Similarity3 inverse() const {
    Similarity3 inv;
    inv.R = R.transpose();
    inv.scale = 1.0 / scale;
    inv.t = -inv.scale * (inv.R * t);
    return inv;
  }
  /// (R, t) as an SE3 (the scale is dropped).
  SE3 rigid_part() const { return SE3(SO3::from_matrix(R), t); }
};

/// Similarity (with_scale) or rigid motion (s = 1) taking src onto dst in the least-squares sense.
Similarity3 umeyama(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale);

/// Rotation about z plus translation (4 DoF) taking src onto dst in the least-squares sense.
Similarity3 umeyama_yaw(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst);

}  // namespace slamkit
