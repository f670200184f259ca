// Motion model of the Victoria Park car (Guivant & Nebot 2001), whose state is the pose of the
// laser, mounted a metres ahead of and b metres left of the rear axle centre. Controls: the
// rear-left wheel encoder speed v_e (Control::v) and the steering angle α (Control::turn).
// The encoder sits H metres left of the axle centre, so the centre speed is
//   v_c = v_e / (1 − tan(α) H / L),
// and with ω = v_c tan(α) / L the laser moves as
//   x' = x + dt (v_c cos θ − ω (a sin θ + b cos θ))
//   y' = y + dt (v_c sin θ + ω (a cos θ − b sin θ))
//   θ' = θ + dt ω.
#pragma once

#include "slamkit/filters/models.h"

namespace slamkit {

struct VictoriaParkGeometry {
  double a = 3.78;   // m, laser ahead of the rear axle (info.txt says 0.95; 3.78 is what most
                     // public implementations use: docs/filters_fastslam.md)
  double b = 0.50;   // m, laser to the left of the vehicle axis
  double H = 0.76;   // m, encoder to the left of the vehicle axis
  double L = 2.83;   // m, wheelbase
};

class VictoriaParkModel final : public MotionModel {
 public:
  VictoriaParkModel(const VictoriaParkGeometry& geometry, double sigma_v, double sigma_steer);
  Eigen::Vector3d predict(const Eigen::Vector3d& pose, const Control& u) const override;
  void jacobians(const Eigen::Vector3d& pose, const Control& u, Eigen::Matrix3d* F_x,
                 Eigen::Matrix<double, 3, 2>* F_u) const override;
  Eigen::Matrix2d control_noise(const Control& u) const override;
  const VictoriaParkGeometry& geometry() const { return geometry_; }

 private:
  VictoriaParkGeometry geometry_;
  double sigma_v_, sigma_steer_;
};

}  // namespace slamkit
