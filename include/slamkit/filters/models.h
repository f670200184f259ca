// Motion and measurement models of the 2D landmark-SLAM filters (pose x = (x, y, θ), point
// landmarks m = (m_x, m_y)). Every filter of the family and the simulator use these, so a
// comparison runs the same models everywhere. Each model gives its Jacobians analytically
// (checked numerically in tests/filters/models_test.cpp).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace slamkit {

/// One control step. `turn` is the steering angle G (bicycle) or the yaw rate ω (unicycle).
struct Control {
  double v = 0;     // m/s, forward speed
  double turn = 0;  // rad (bicycle steering) or rad/s (unicycle yaw rate)
  double dt = 0;    // s
};

/// One range-bearing observation. `id` ≥ 0 is the true landmark identity (known
/// association); id < 0 means unknown (the filter's data association decides).
struct RangeBearing {
  int id = -1;
  double range = 0;    // m
  double bearing = 0;  // rad, wrapped to (−π, π], relative to the vehicle heading
};

/// x' = f(x, u) with control noise u ~ N(u, Q(u)).
class MotionModel {
 public:
  virtual ~MotionModel() = default;
  virtual Eigen::Vector3d predict(const Eigen::Vector3d& pose, const Control& u) const = 0;
  /// F_x = ∂f/∂x (3×3), F_u = ∂f/∂(v, turn) (3×2) at (pose, u).
  virtual void jacobians(const Eigen::Vector3d& pose, const Control& u, Eigen::Matrix3d* F_x,
                         Eigen::Matrix<double, 3, 2>* F_u) const = 0;
  /// Q(u): covariance of (v, turn).
  virtual Eigen::Matrix2d control_noise(const Control& u) const = 0;
};

/// Bicycle: x' = x + v dt cos(θ+G), y' = y + v dt sin(θ+G), θ' = θ + v dt sin(G)/L.
class BicycleModel final : public MotionModel {
 public:
  BicycleModel(double wheelbase, double sigma_v, double sigma_steer);
  Eigen::Vector3d predict(const Eigen::Vector3d& pose, const Control& u) const override;
  void jacobians(const Eigen::Vector3d& pose, const Control& u, Eigen::Matrix3d* F_x,
                 Eigen::Matrix<double, 3, 2>* F_u) const override;
  Eigen::Matrix2d control_noise(const Control& u) const override;
  double wheelbase() const { return wheelbase_; }

 private:
  double wheelbase_, sigma_v_, sigma_steer_;
};

/// Unicycle (odometry v, ω, e.g. MRCLAM): x' = x + v dt cos θ, y' = y + v dt sin θ,
/// θ' = θ + ω dt. Noise: σ_v, σ_ω constant plus a part proportional to |v| and |ω|.
class UnicycleModel final : public MotionModel {
 public:
  UnicycleModel(double sigma_v, double sigma_w, double sigma_v_per_v = 0,
                double sigma_w_per_w = 0);
  Eigen::Vector3d predict(const Eigen::Vector3d& pose, const Control& u) const override;
  void jacobians(const Eigen::Vector3d& pose, const Control& u, Eigen::Matrix3d* F_x,
                 Eigen::Matrix<double, 3, 2>* F_u) const override;
  Eigen::Matrix2d control_noise(const Control& u) const override;

 private:
  double sigma_v_, sigma_w_, sigma_v_per_v_, sigma_w_per_w_;
};

/// z = h(x, m) = (|m − p|, atan2(m_y − y, m_x − x) − θ), noise R = diag(σ_r², σ_b²).
class RangeBearingModel {
 public:
  RangeBearingModel(double sigma_range, double sigma_bearing);
  /// Predicted (range, bearing), bearing wrapped.
  Eigen::Vector2d predict(const Eigen::Vector3d& pose, const Eigen::Vector2d& landmark) const;
  /// H_x = ∂h/∂x (2×3), H_m = ∂h/∂m (2×2).
  void jacobians(const Eigen::Vector3d& pose, const Eigen::Vector2d& landmark,
                 Eigen::Matrix<double, 2, 3>* H_x, Eigen::Matrix2d* H_m) const;
  /// Landmark from a pose and an observation: m = g(x, z), with G_x = ∂g/∂x, G_z = ∂g/∂z.
  Eigen::Vector2d inverse(const Eigen::Vector3d& pose, const RangeBearing& z,
                          Eigen::Matrix<double, 2, 3>* G_x = nullptr,
                          Eigen::Matrix2d* G_z = nullptr) const;
  /// Innovation z − h with the bearing wrapped to (−π, π].
  static Eigen::Vector2d innovation(const RangeBearing& z, const Eigen::Vector2d& predicted);
  Eigen::Matrix2d noise() const;

 private:
  double sigma_range_, sigma_bearing_;
};

}  // namespace slamkit
