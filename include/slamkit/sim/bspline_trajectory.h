// BSplineTrajectory: a continuous-time body trajectory T_world_body(t), a uniform cumulative
// cubic B-spline on SO(3) × R³ (rotation and position split, the form of Sommer et al. 2020
// and of the OpenVINS simulator), fitted to a sampled path by least squares.
//
// Knots t_k = t0 + (k − 1)·dt for control points k = 0..N−1 (R_k, p_k); valid on
// [t0, t0 + (N − 3)·dt]. On segment i (t ∈ [t0 + i dt, t0 + (i+1) dt), u = (t − t0)/dt − i):
//   R(t) = R_i · Π_{j=1..3} Exp(B̃_j(u) · d_j),   d_j = Log(R_{i+j−1}⁻¹ R_{i+j})
//   p(t) = p_i + Σ_{j=1..3} B̃_j(u) · (p_{i+j} − p_{i+j−1})
// with the cumulative cubic basis B̃(u) = C·[1, u, u², u³]ᵀ,
//   C = 1/6 [[6, 0, 0, 0], [5, 3, −3, 1], [1, 3, 3, −2], [0, 0, 0, 1]].
// Derivatives are analytic: ω_body = ω_3 with ω_0 = 0, ω_j = Exp(B̃_j d_j)ᵀ ω_{j−1} + B̃'_j d_j
// (Rᵀ Ṙ = [ω_body]×), v_world = ṗ, a_world = p̈ (polynomials in u). The spline is C² in
// position and C² in rotation, so the simulated IMU is continuous.
// Immutable after construction; evaluation is const and thread-safe.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/core/trajectory.h"
#include "slamkit/geometry/se3.h"
#include "slamkit/geometry/so3.h"

namespace slamkit {

struct BSplineFitOptions {
  double knot_spacing = 0.1;      ///< dt [s]
  int max_iterations = 10;        ///< Gauss-Newton iterations on the rotations
  double smoothness_weight = 1e-3;  ///< weight of the second differences of the control points
                                    ///< (keeps knots without samples, in ground-truth gaps, defined)
};

/// Residuals of the fitted spline at the samples of the path it was fitted to.
struct BSplineFitReport {
  std::size_t samples = 0;
  std::size_t control_points = 0;
  int iterations = 0;
  double position_rmse = 0.0;  ///< m
  double position_max = 0.0;   ///< m
  double rotation_rmse = 0.0;  ///< rad, ‖Log(R_path⁻¹ R(t))‖
  double rotation_max = 0.0;   ///< rad
};

/// Pose and derivatives at one time.
struct BSplineState {
  SE3 T_world_body;
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();       ///< ṗ [m/s]
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();       ///< p̈ [m/s²] (kinematic, no gravity)
  Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();    ///< angular velocity in the body frame [rad/s]
  /// Linear acceleration in the body frame, R(t)ᵀ p̈ [m/s²].
  Eigen::Vector3d a_body() const { return T_world_body.rotation().inverse().act(a_world); }
};

class BSplineTrajectory {
 public:
  /// Throws std::invalid_argument unless dt > 0, there are at least 4 control points of each
  /// kind, the same number, and everything is finite.
  BSplineTrajectory(double t0, double dt, std::vector<SO3> rotations, std::vector<Eigen::Vector3d> positions);

  /// Least-squares fit to the poses of `path` (at least 2 samples, spanning > 0 s): position is
  /// linear least squares, rotation Gauss-Newton on Σ ‖Log(R_path⁻¹ R(t))‖², both with a weak
  /// second-difference smoothness term. Throws InputError (field "path") on unusable paths.
  static BSplineTrajectory fit(const Trajectory& path, const BSplineFitOptions& options = {},
                               BSplineFitReport* report = nullptr);

  double start_time() const { return t0_; }
  double end_time() const { return t0_ + static_cast<double>(rotations_.size() - 3) * dt_; }
  double knot_spacing() const { return dt_; }
  const std::vector<SO3>& control_rotations() const { return rotations_; }
  const std::vector<Eigen::Vector3d>& control_positions() const { return positions_; }

  /// Throws std::out_of_range for t outside [start_time(), end_time()] (or not finite).
  BSplineState evaluate(double t) const;
  SE3 pose(double t) const;

  /// Residuals of this spline at the samples of `path` inside its time range.
  BSplineFitReport residuals(const Trajectory& path) const;

 private:
  double t0_, dt_;
  std::vector<SO3> rotations_;
  std::vector<Eigen::Vector3d> positions_;
};

}  // namespace slamkit
