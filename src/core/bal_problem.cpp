#include "slamkit/core/bal_problem.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

namespace slamkit {
namespace {

Eigen::Matrix3d angle_axis_matrix(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-12) {  // first order: R ≈ I + [w]×
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    R(0, 1) = -w.z(), R(0, 2) = w.y(), R(1, 0) = w.z(), R(1, 2) = -w.x(), R(2, 0) = -w.y(), R(2, 1) = w.x();
    return R;
  }
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

Eigen::Vector2d bal_project(const BalProblem::CameraParams& c, const Eigen::Vector3d& X, double* P_z) {
  const Eigen::Vector3d P = angle_axis_matrix(c.head<3>()) * X + c.segment<3>(3);
  if (P_z) *P_z = P.z();
  const Eigen::Vector2d p = -P.head<2>() / P.z();
  const double n2 = p.squaredNorm();
  return c[6] * (1.0 + c[7] * n2 + c[8] * n2 * n2) * p;
}

Eigen::Vector3d bal_camera_center(const BalProblem::CameraParams& c) {
  return -(angle_axis_matrix(c.head<3>()).transpose() * c.segment<3>(3));
}

void bal_set_camera_center(BalProblem::CameraParams& cam, const Eigen::Vector3d& c) {
  cam.segment<3>(3) = -(angle_axis_matrix(cam.head<3>()) * c);
}

double bal_cost(const BalProblem& p) {
  double s = 0.0;
  for (const BalObservation& o : p.observations)
    s += (bal_project(p.cameras[o.camera], p.points[o.point]) - o.pixel).squaredNorm();
  return 0.5 * s;
}

double normalize_bal(BalProblem& p) {
  if (p.points.empty()) return 1.0;
  Eigen::Vector3d m;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> v(p.points.size());
    for (std::size_t j = 0; j < v.size(); ++j) v[j] = p.points[j][a];
    m[a] = median(std::move(v));
  }
  std::vector<double> dev(p.points.size());
  for (std::size_t j = 0; j < dev.size(); ++j) dev[j] = (p.points[j] - m).lpNorm<1>();
  const double d = median(std::move(dev));
  const double s = d > 0.0 && std::isfinite(d) ? 100.0 / d : 1.0;
  for (Eigen::Vector3d& X : p.points) X = s * (X - m);
  for (BalProblem::CameraParams& c : p.cameras) bal_set_camera_center(c, s * (bal_camera_center(c) - m));
  return s;
}

void perturb_bal(BalProblem& p, const BalPerturbation& q) {
  std::mt19937_64 rng(q.seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Vector3d& X : p.points)
    if (q.point_sigma > 0.0)
      for (int a = 0; a < 3; ++a) X[a] += q.point_sigma * n(rng);
  for (BalProblem::CameraParams& c : p.cameras) {
    const Eigen::Vector3d centre = bal_camera_center(c);
    if (q.rotation_sigma > 0.0)
      for (int a = 0; a < 3; ++a) c[a] += q.rotation_sigma * n(rng);
    Eigen::Vector3d moved = centre;
    if (q.translation_sigma > 0.0)
      for (int a = 0; a < 3; ++a) moved[a] += q.translation_sigma * n(rng);
    bal_set_camera_center(c, moved);
  }
}

}  // namespace slamkit
