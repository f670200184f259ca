// Readers of Kalibr calibration files (as shipped with OpenVINS for TUM-VI and EuRoC):
//
//   camchain (imucam) file: per camera "camN:" with camera_model (pinhole), distortion_model
//     (radtan | equidistant | none), intrinsics [fu, fv, cu, cv], distortion_coeffs,
//     resolution [w, h] and either T_cam_imu (IMU → camera, TUM-VI file) or T_imu_cam
//     (camera → IMU, EuRoC file) as 4×4 rows.
//   imu file: "imu0:" with accelerometer/gyroscope noise densities and random walks and
//     update_rate.
// The YAML is read by a strict subset parser (src/io/yaml_subset.h). Every missing, extra-sized
// or malformed field throws InputError "FILE:LINE: field 'cam0.intrinsics': ...".
#pragma once

#include <istream>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

struct CameraCalibration {
  std::string name;              ///< "cam0"
  std::string distortion_model;  ///< "radtan", "equidistant" or "none"
  std::vector<double> intrinsics;  ///< fx, fy, cx, cy
  std::vector<double> distortion;  ///< k1 k2 p1 p2 (radtan) or k1..k4 (equidistant)
  int width = 0, height = 0;
  SE3 T_cam_imu;                 ///< p_cam = T_cam_imu · p_imu
  std::shared_ptr<CameraModel> model;  ///< the model built from the fields above
};

/// Continuous-time IMU noise (Kalibr imu.yaml).
struct ImuCalibration {
  double accelerometer_noise_density = 0.0;  ///< m/s²/√Hz
  double accelerometer_random_walk = 0.0;    ///< m/s³/√Hz
  double gyroscope_noise_density = 0.0;      ///< rad/s/√Hz
  double gyroscope_random_walk = 0.0;        ///< rad/s²/√Hz
  double update_rate = 0.0;                  ///< Hz
};

/// Every "camN" entry of a camchain file, in file order (at least one).
std::vector<CameraCalibration> read_kalibr_camchain(std::istream& in, const std::string& source);
std::vector<CameraCalibration> read_kalibr_camchain(const std::string& path);
/// The "imu0" entry of a Kalibr IMU file.
ImuCalibration read_kalibr_imu(std::istream& in, const std::string& source);
ImuCalibration read_kalibr_imu(const std::string& path);

}  // namespace slamkit
