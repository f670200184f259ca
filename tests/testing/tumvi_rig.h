// The TUM-VI camera rig for simulator and VIO tests, without the dataset: cam0's equidistant
// fisheye at 512×512 and its camera–IMU extrinsics (values of tumvi/calib, Kalibr's
// T_cam_imu), and a handheld-like circle path fitted as a B-spline.
#pragma once

#include <cmath>
#include <memory>

#include "slamkit/core/trajectory.h"
#include "slamkit/geometry/camera_models.h"
#include "slamkit/sim/bspline_trajectory.h"

namespace slamkit::testing {

inline std::shared_ptr<CameraModel> tumvi_camera() {
  return std::make_shared<EquidistantCamera>(190.97847715128717, 190.9733070521226, 254.93170605935475,
                                             256.8974428996504, 0.0034823894022493434, 0.0007150348452162257,
                                             -0.0020532361418706202, 0.00020293673591811182, 512, 512);
}

inline SE3 tumvi_T_cam_imu() {
  Eigen::Matrix<double, 3, 4> T;
  T << -0.9995250378696743, 0.029615343885863205, -0.008522328211654736, 0.04727988224914392,
      0.0075019185074052044, -0.03439736061393144, -0.9993800792498829, -0.047443232143367084,
      -0.02989013031643309, -0.998969345370175, 0.03415885127385616, -0.0681999605066297;
  return SE3::from_matrix(T);
}

/// A 2 m circle at 1.4 m height (0.4 rad/s), 0.1 m vertical sway, swaying rotation.
inline BSplineTrajectory circle_path(double duration = 20.0) {
  Trajectory path;
  for (double t = 0.0; t <= duration; t += 0.01) {
    const double a = 0.4 * t;
    const Eigen::Vector3d p(2.0 * std::cos(a), 2.0 * std::sin(a), 1.4 + 0.1 * std::sin(1.3 * t));
    const SO3 R = SO3::exp(Eigen::Vector3d(0, 0, a + M_PI)) * SO3::exp(Eigen::Vector3d(0.2 * std::sin(0.7 * t), 0.1, 0));
    path.push_back(t, SE3(R, p));
  }
  return BSplineTrajectory::fit(path);
}

}  // namespace slamkit::testing
