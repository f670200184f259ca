// IMU stream reader: the ASL/EuRoC CSV `mav0/imu0/data.csv` layout used by EuRoC and TUM-VI,
//   timestamp [ns], w_x, w_y, w_z [rad/s], a_x, a_y, a_z [m/s²]
// one '#' header line (or a first line starting with a letter). Strict: a wrong field count,
// a bad number or a stamp that does not increase throws InputError "FILE:LINE: field ...".
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "slamkit/core/imu_measurement.h"

namespace slamkit {

std::vector<ImuMeasurement> read_imu_csv(std::istream& in, const std::string& source);
/// Reads a file; an empty stream (no samples) is an error.
std::vector<ImuMeasurement> read_imu_csv(const std::string& path);

}  // namespace slamkit
