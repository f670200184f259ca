// An analytic rigid-body motion and its exact IMU readings, for preintegration and VIO tests.
//   p(t) = (a sin(ω₁t), b cos(ω₂t) − b, c t² / 2 + d sin(t))      (world, z up)
//   R(t) = Exp(α t e_z) · Exp(β sin(t) e_y)                        (R_world_imu)
//   body rate ω(t) = Exp(β sin t e_y)ᵀ α e_z + β cos(t) e_y,  specific force f = Rᵀ (p̈ − g).
// `scale` shrinks or grows the motion (0 gives a sensor at rest with constant heading).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "slamkit/core/imu_measurement.h"
#include "slamkit/factors/imu_state.h"

namespace slamkit::testing {

struct AnalyticMotion {
  double scale = 1.0;
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);

  Eigen::Vector3d position(double t) const {
    return scale * Eigen::Vector3d(1.5 * std::sin(0.9 * t), 1.0 * std::cos(0.7 * t) - 1.0, 0.05 * t * t + 0.3 * std::sin(t));
  }
  Eigen::Vector3d velocity(double t) const {
    return scale * Eigen::Vector3d(1.35 * std::cos(0.9 * t), -0.7 * std::sin(0.7 * t), 0.1 * t + 0.3 * std::cos(t));
  }
  Eigen::Vector3d acceleration(double t) const {
    return scale * Eigen::Vector3d(-1.215 * std::sin(0.9 * t), -0.49 * std::cos(0.7 * t), 0.1 - 0.3 * std::sin(t));
  }
  double alpha() const { return 0.6 * scale; }
  double beta() const { return 0.4 * scale; }
  SO3 rotation(double t) const {
    return SO3::exp(Eigen::Vector3d(0, 0, alpha() * t)) * SO3::exp(Eigen::Vector3d(0, beta() * std::sin(t), 0));
  }
  Eigen::Vector3d body_rate(double t) const {
    const SO3 R2 = SO3::exp(Eigen::Vector3d(0, beta() * std::sin(t), 0));
    return R2.inverse().act(Eigen::Vector3d(0, 0, alpha())) + Eigen::Vector3d(0, beta() * std::cos(t), 0);
  }
  ImuState state(double t, const ImuBias& bias = {}) const {
    ImuState s;
    s.R = rotation(t), s.p = position(t), s.v = velocity(t), s.bg = bias.gyro, s.ba = bias.accel;
    return s;
  }
  ImuMeasurement measurement(double t, const ImuBias& bias = {}) const {
    ImuMeasurement m;
    m.stamp = t;
    m.gyro = body_rate(t) + bias.gyro;
    m.accel = rotation(t).inverse().act(acceleration(t) - gravity) + bias.accel;
    return m;
  }
  /// Samples at `rate` Hz over [t0, t1] (both included), exact plus the given constant bias.
  std::vector<ImuMeasurement> samples(double t0, double t1, double rate, const ImuBias& bias = {}) const {
    std::vector<ImuMeasurement> out;
    const int n = static_cast<int>(std::round((t1 - t0) * rate));
    for (int k = 0; k <= n; ++k) out.push_back(measurement(t0 + k / rate, bias));
    return out;
  }
};

}  // namespace slamkit::testing
