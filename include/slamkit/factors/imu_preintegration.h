// On-manifold IMU preintegration (Forster et al., "On-Manifold Preintegration for Real-Time
// Visual-Inertial Odometry", T-RO 2017) with midpoint integration (as VINS-Mono), and the
// IMU factor between two ImuStates.
//
// Between keyframes i and j, with the linearization biases b̄_g, b̄_a, every IMU interval
// [t_k, t_k+1] (dt) is integrated with the midpoint rule:
//   ω = ½(ω_k + ω_k+1) − b̄_g,          ΔR_k+1 = ΔR_k Exp(ω dt)
//   ā = ½(ΔR_k (a_k − b̄_a) + ΔR_k+1 (a_k+1 − b̄_a))
//   Δp_k+1 = Δp_k + Δv_k dt + ½ ā dt²,  Δv_k+1 = Δv_k + ā dt
// The error state η = [δφ, δv, δp, δb_g, δb_a] (ΔR_true = ΔR Exp(δφ)) follows η_k+1 = F η_k + G n
// with F the exact derivative of the step above (so the bias Jacobians, the 9×6 block of
// Π F, are the exact first-order derivatives of the discrete integration), and
// n = [n_g, n_a, n_bg, n_ba] of discrete covariance diag(σ_g²/dt, σ_a²/dt, σ_bg² dt, σ_ba² dt)
// from the continuous densities σ (Forster eq. 40 and the README of the datasets):
//   P_k+1 = F P_k Fᵀ + G Q_d Gᵀ  (15×15).
// Bias update to first order (Forster eq. 44), δb = b − b̄:
//   ΔR(b) = ΔR Exp(J_R^g δb_g), Δv(b) = Δv + J_v^g δb_g + J_v^a δb_a, Δp(b) likewise.
//
// ImuFactor residual (15) with gravity g in the world frame (e.g. (0, 0, −9.81)), Δt = t_j − t_i:
//   r_R = Log(ΔR(b_i)ᵀ R_iᵀ R_j)
//   r_v = R_iᵀ (v_j − v_i − g Δt) − Δv(b_i)
//   r_p = R_iᵀ (p_j − p_i − v_i Δt − ½ g Δt²) − Δp(b_i)
//   r_bg = b_g,j − b_g,i,   r_ba = b_a,j − b_a,i
// whitened by the propagated 15×15 covariance. Analytic Jacobians (see the .cpp).
// ImuPreintegration is a value type; ImuFactor is immutable and thread-safe.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "slamkit/core/factor.h"
#include "slamkit/core/imu_measurement.h"
#include "slamkit/core/trajectory.h"
#include "slamkit/factors/imu_state.h"

namespace slamkit {

/// Continuous-time IMU noise: white-noise densities and bias random walks.
struct ImuNoise {
  double gyro_noise_density = 1.6e-4;   ///< σ_g  [rad/s/√Hz]
  double accel_noise_density = 2.8e-3;  ///< σ_a  [m/s²/√Hz]
  double gyro_random_walk = 2.2e-5;     ///< σ_bg [rad/s²/√Hz]
  double accel_random_walk = 8.6e-4;    ///< σ_ba [m/s³/√Hz]
  static ImuNoise tumvi() { return {}; }  ///< TUM-VI BMI160 (datasets/vio/README.md)
  static ImuNoise euroc() { return {1.6968e-4, 2.0e-3, 1.9393e-5, 3.0e-3}; }  ///< EuRoC ADIS16448
};

class ImuPreintegration {
 public:
  using Matrix15 = Eigen::Matrix<double, 15, 15>;
  using Matrix96 = Eigen::Matrix<double, 9, 6>;

  ImuPreintegration() = default;
  /// Throws std::invalid_argument if a noise value is not finite or not positive.
  ImuPreintegration(const ImuBias& linearization_bias, const ImuNoise& noise);

  /// One midpoint step over [t_k, t_k + dt] from the samples at both ends (dt > 0).
  void integrate(double dt, const Eigen::Vector3d& gyro0, const Eigen::Vector3d& accel0,
                 const Eigen::Vector3d& gyro1, const Eigen::Vector3d& accel1);
  /// Integrates `samples` (stamps increasing) over [t0, t1], interpolating linearly at both
  /// ends; throws std::invalid_argument if the samples do not cover [t0, t1] or t1 ≤ t0.
  void integrate_between(const std::vector<ImuMeasurement>& samples, double t0, double t1);
  /// Restarts from identity with new linearization biases, keeping the noise.
  void reset(const ImuBias& linearization_bias);

  double dt() const { return dt_; }
  const ImuBias& linearization_bias() const { return bias_; }
  const ImuNoise& noise() const { return noise_; }
  const SO3& delta_R() const { return dR_; }
  const Eigen::Vector3d& delta_v() const { return dv_; }
  const Eigen::Vector3d& delta_p() const { return dp_; }
  /// Covariance of [δφ, δv, δp, b_g,j − b_g,i, b_a,j − b_a,i].
  const Matrix15& covariance() const { return P_; }
  /// ∂[δφ, δv, δp]/∂[δb_g, δb_a] (rows 0-2: J_R^g and 0; rows 3-5: J_v^g, J_v^a; rows 6-8: J_p).
  Matrix96 bias_jacobian() const { return J_.block<9, 6>(0, 9); }

  /// The preintegrated deltas at bias b, to first order in b − b̄.
  SO3 delta_R(const ImuBias& b) const;
  Eigen::Vector3d delta_v(const ImuBias& b) const;
  Eigen::Vector3d delta_p(const ImuBias& b) const;

  /// The state at t_i + Δt predicted from `state_i` (its biases held) under gravity g_world.
  ImuState predict(const ImuState& state_i, const Eigen::Vector3d& g_world) const;

 private:
  ImuBias bias_;
  ImuNoise noise_;
  double dt_ = 0.0;
  SO3 dR_;
  Eigen::Vector3d dv_ = Eigen::Vector3d::Zero(), dp_ = Eigen::Vector3d::Zero();
  Matrix15 P_ = Matrix15::Zero();
  Matrix15 J_ = Matrix15::Identity();  // Π F: ∂η_k/∂η_0, its bias columns are the bias Jacobians
};

class ImuFactor final : public FactorN<15, ImuState, ImuState> {
 public:
  /// Throws NumericalError if the preintegrated covariance is not positive definite (Δt = 0).
  ImuFactor(Key state_i, Key state_j, ImuPreintegration preintegration, const Eigen::Vector3d& g_world);
  Residual error(const ImuState& xi, const ImuState& xj, Jacobian<ImuState>* J_i,
                 Jacobian<ImuState>* J_j) const override;
  const ImuPreintegration& preintegration() const { return pim_; }
  const Eigen::Vector3d& gravity() const { return g_; }

 private:
  ImuPreintegration pim_;
  Eigen::Vector3d g_;
};

}  // namespace slamkit
