// Checking IMU preintegration against ground truth: integrate a real IMU stream between two
// ground-truth states and compare with the propagated covariance (NEES of the 9-dof error
// [r_R, r_v, r_p] of the ImuFactor at the ground-truth states).
//
// Ground truth is not exact, and for TUM-VI it has no velocity, so the check models it:
//   * velocities by a local quadratic least-squares fit of the mocap positions over
//     ±half_width around each sample; its covariance σ² [(XᵀX)⁻¹]₁₁ with σ² the larger of
//     the pooled and the local residual variance of the fits (the local one absorbs the
//     quadratic model's error where the motion is jerky);
//   * pose noise σ_p (position) and σ_R (rotation, from the same fit of Log(R_kᵀ R_t)).
// These enter the NEES covariance through the factor's Jacobians at both ends:
//   P = P_imu + J_i Σ_gt J_iᵀ + J_j Σ_gt J_jᵀ   (Σ_gt = diag(σ_R², σ_v², σ_p²)).
// Biases come from the ground truth (EuRoC) or from a weighted least-squares fit of constant
// biases over the sequence's windows (fit_constant_bias).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/core/imu_measurement.h"
#include "slamkit/core/trajectory.h"
#include "slamkit/factors/imu_preintegration.h"

namespace slamkit {

/// Result of differentiate_ground_truth: pooled residual σ of the local fits and, per sample,
/// the velocity std (NaN where the fit window was incomplete, e.g. in mocap gaps).
struct GroundTruthDifferentiation {
  double position_sigma = 0.0;  ///< [m] pooled RMS residual of the position fits (per axis)
  double rotation_sigma = 0.0;  ///< [rad] pooled RMS residual of the rotation fits (per axis)
  std::vector<double> velocity_sigma;  ///< [m/s] per sample (per axis)
};

/// Fills v_world of every sample by a local quadratic fit over ±half_width seconds (at least
/// 2 samples each side, spanning at least 0.6·half_width each side, else v is left empty).
GroundTruthDifferentiation differentiate_ground_truth(Trajectory& gt, double half_width);

/// A window [i, j] of ground-truth samples over which the IMU is integrated.
struct ImuWindow {
  std::size_t i = 0, j = 0;
  double t0 = 0.0, t1 = 0.0;
};
/// Non-overlapping windows of `length` seconds (±10 %) whose ends have velocities and whose
/// ground truth has no gap longer than max_gap, inside the IMU stream.
std::vector<ImuWindow> select_imu_windows(const Trajectory& gt, const std::vector<ImuMeasurement>& imu, double length,
                                          double max_gap);

struct ImuWindowError {
  Eigen::Matrix<double, 9, 1> residual;     ///< [r_R, r_v, r_p] at the ground-truth states
  Eigen::Matrix<double, 9, 9> P_imu;        ///< propagated IMU covariance
  Eigen::Matrix<double, 9, 9> P_gt;         ///< ground-truth error mapped through the factor
  Eigen::Matrix<double, 9, 6> J_bias;       ///< ∂residual/∂[b_g, b_a]
  double nees_imu_only() const;             ///< rᵀ P_imu⁻¹ r
  double nees() const;                      ///< rᵀ (P_imu + P_gt)⁻¹ r
};

/// gt_sigma_i/j: [σ_R, σ_v, σ_p] of the ground truth at the two ends (per axis).
ImuWindowError imu_window_error(const std::vector<ImuMeasurement>& imu, const TrajectorySample& a,
                                const TrajectorySample& b, const ImuBias& bias, const ImuNoise& noise,
                                const Eigen::Vector3d& g_world, const Eigen::Vector3d& gt_sigma_i,
                                const Eigen::Vector3d& gt_sigma_j);

/// Constant biases minimizing Σ_w r_wᵀ P_w⁻¹ r_w over the windows (Gauss-Newton, re-integrating
/// at each iterate). gt_sigma(k) gives the [σ_R, σ_v, σ_p] of sample k. With g_tilted non-null
/// the direction of gravity in the ground-truth frame is fitted too (2 more unknowns: a tilt
/// g ← Exp([θx, θy, 0]) g, since a mocap frame's z is levelled only to a fraction of a degree)
/// and returned there.
ImuBias fit_constant_bias(const std::vector<ImuMeasurement>& imu, const Trajectory& gt,
                          const std::vector<ImuWindow>& windows, const ImuNoise& noise, const Eigen::Vector3d& g_world,
                          const std::vector<Eigen::Vector3d>& gt_sigma, int iterations = 3,
                          Eigen::Vector3d* g_tilted = nullptr);

}  // namespace slamkit
