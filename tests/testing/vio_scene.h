// A synthetic visual-inertial scene for VIO tests: the AnalyticMotion (imu_motion.h), a
// forward-looking pinhole camera, landmarks on a cylinder around the path, noisy IMU at
// 200 Hz with constant biases and noisy pixel observations at 20 Hz with track ids.
#pragma once

#include <memory>
#include <random>
#include <vector>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/sliding_window_estimator.h"
#include "testing/imu_motion.h"

namespace slamkit::testing {

struct VioScene {
  AnalyticMotion motion;
  std::shared_ptr<const CameraModel> camera = std::make_shared<PinholeCamera>(300.0, 300.0, 320.0, 240.0, 640, 480);
  // Camera z forward = IMU x, camera x = −IMU y, camera y = −IMU z.
  SE3 T_imu_cam = SE3(SO3::from_matrix((Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished()),
                      Eigen::Vector3d(0.05, 0.0, 0.02));
  ImuBias bias{Eigen::Vector3d(0.003, -0.002, 0.001), Eigen::Vector3d(0.05, -0.03, 0.02)};
  ImuNoise noise = ImuNoise::tumvi();
  double pixel_sigma = 1.0;
  std::vector<Eigen::Vector3d> landmarks;
  std::vector<ImuMeasurement> imu;
  std::vector<CameraFrame> frames;

  VioScene(double t0, double t1, unsigned seed, int num_landmarks = 800) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> n;
    for (int i = 0; i < num_landmarks; ++i) {
      const double a = 2 * kPi * u(rng), r = 4.0 + 2.0 * u(rng), z = -1.5 + 3.5 * u(rng);
      landmarks.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
    for (const ImuMeasurement& m : motion.samples(t0 - 0.05, t1 + 0.05, 200.0, bias)) {
      ImuMeasurement x = m;
      for (int a = 0; a < 3; ++a) {
        x.gyro(a) += noise.gyro_noise_density * std::sqrt(200.0) * n(rng);
        x.accel(a) += noise.accel_noise_density * std::sqrt(200.0) * n(rng);
      }
      imu.push_back(x);
    }
    const int nf = static_cast<int>(std::round((t1 - t0) * 20.0));
    for (int k = 1; k <= nf; ++k) {
      CameraFrame f;
      f.stamp = t0 + k / 20.0;
      const SE3 T_cw = (motion.state(f.stamp).pose() * T_imu_cam).inverse();
      for (std::size_t i = 0; i < landmarks.size(); ++i) {
        const Eigen::Vector3d p = T_cw.act(landmarks[i]);
        Eigen::Vector2d uv;
        if (p.z() < 0.3 || !camera->project(p, &uv) || !camera->in_image(uv, 2.0)) continue;
        f.features.push_back({i, uv + pixel_sigma * Eigen::Vector2d(n(rng), n(rng))});
      }
      frames.push_back(std::move(f));
    }
  }
};

}  // namespace slamkit::testing
