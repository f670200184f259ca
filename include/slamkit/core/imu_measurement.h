// ImuMeasurement: one sample of a 6-axis IMU, the exchange type between the IMU readers
// (io/imu_io.h), simulators and the preintegration (factors/imu_preintegration.h).
// gyro = ω of the IMU in its own frame [rad/s], accel = specific force f = Rᵀ(a − g) in the
// IMU frame [m/s²] (+9.81 along "up" at rest). Plain value type.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>

namespace slamkit {

struct ImuMeasurement {
  double stamp = 0.0;                    ///< seconds
  std::optional<std::int64_t> stamp_ns;  ///< exact source stamp, when read from a file
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};

}  // namespace slamkit
