#include "slamkit/filters/models.h"

#include <cmath>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {

namespace {
void require_positive(double value, const char* field) {
  if (!(value > 0) || !std::isfinite(value))
    throw InputError("filter model", 0, field, "must be a positive finite number");
}
void require_non_negative(double value, const char* field) {
  if (!(value >= 0) || !std::isfinite(value))
    throw InputError("filter model", 0, field, "must be a non-negative finite number");
}
}  // namespace

BicycleModel::BicycleModel(double wheelbase, double sigma_v, double sigma_steer)
    : wheelbase_(wheelbase), sigma_v_(sigma_v), sigma_steer_(sigma_steer) {
  require_positive(wheelbase, "wheelbase");
  require_non_negative(sigma_v, "sigma_v");
  require_non_negative(sigma_steer, "sigma_steer");
}

Eigen::Vector3d BicycleModel::predict(const Eigen::Vector3d& p, const Control& u) const {
  const double a = p.z() + u.turn, s = u.v * u.dt;
  return {p.x() + s * std::cos(a), p.y() + s * std::sin(a),
          wrap_angle(p.z() + s * std::sin(u.turn) / wheelbase_)};
}

void BicycleModel::jacobians(const Eigen::Vector3d& p, const Control& u, Eigen::Matrix3d* F_x,
                             Eigen::Matrix<double, 3, 2>* F_u) const {
  const double a = p.z() + u.turn, s = u.v * u.dt, c = std::cos(a), sn = std::sin(a);
  if (F_x) *F_x << 1, 0, -s * sn, 0, 1, s * c, 0, 0, 1;
  if (F_u)
    *F_u << u.dt * c, -s * sn, u.dt * sn, s * c, u.dt * std::sin(u.turn) / wheelbase_,
        s * std::cos(u.turn) / wheelbase_;
}

Eigen::Matrix2d BicycleModel::control_noise(const Control&) const {
  return Eigen::Vector2d(sigma_v_ * sigma_v_, sigma_steer_ * sigma_steer_).asDiagonal();
}

UnicycleModel::UnicycleModel(double sigma_v, double sigma_w, double sigma_v_per_v,
                             double sigma_w_per_w)
    : sigma_v_(sigma_v), sigma_w_(sigma_w), sigma_v_per_v_(sigma_v_per_v),
      sigma_w_per_w_(sigma_w_per_w) {
  require_non_negative(sigma_v, "sigma_v");
  require_non_negative(sigma_w, "sigma_w");
  require_non_negative(sigma_v_per_v, "sigma_v_per_v");
  require_non_negative(sigma_w_per_w, "sigma_w_per_w");
}

Eigen::Vector3d UnicycleModel::predict(const Eigen::Vector3d& p, const Control& u) const {
  const double s = u.v * u.dt;
  return {p.x() + s * std::cos(p.z()), p.y() + s * std::sin(p.z()),
          wrap_angle(p.z() + u.turn * u.dt)};
}

void UnicycleModel::jacobians(const Eigen::Vector3d& p, const Control& u, Eigen::Matrix3d* F_x,
                              Eigen::Matrix<double, 3, 2>* F_u) const {
  const double s = u.v * u.dt, c = std::cos(p.z()), sn = std::sin(p.z());
  if (F_x) *F_x << 1, 0, -s * sn, 0, 1, s * c, 0, 0, 1;
  if (F_u) *F_u << u.dt * c, 0, u.dt * sn, 0, 0, u.dt;
}

Eigen::Matrix2d UnicycleModel::control_noise(const Control& u) const {
  const double sv = sigma_v_ + sigma_v_per_v_ * std::abs(u.v);
  const double sw = sigma_w_ + sigma_w_per_w_ * std::abs(u.turn);
  return Eigen::Vector2d(sv * sv, sw * sw).asDiagonal();
}

RangeBearingModel::RangeBearingModel(double sigma_range, double sigma_bearing)
    : sigma_range_(sigma_range), sigma_bearing_(sigma_bearing) {
  require_positive(sigma_range, "sigma_range");
  require_positive(sigma_bearing, "sigma_bearing");
}

Eigen::Vector2d RangeBearingModel::predict(const Eigen::Vector3d& p,
                                           const Eigen::Vector2d& m) const {
  const Eigen::Vector2d d = m - p.head<2>();
  return {d.norm(), wrap_angle(std::atan2(d.y(), d.x()) - p.z())};
}

void RangeBearingModel::jacobians(const Eigen::Vector3d& p, const Eigen::Vector2d& m,
                                  Eigen::Matrix<double, 2, 3>* H_x, Eigen::Matrix2d* H_m) const {
  const Eigen::Vector2d d = m - p.head<2>();
  const double q = d.squaredNorm(), r = std::sqrt(q);
  if (!(r > 0)) throw InputError("range-bearing model", 0, "landmark", "landmark at the vehicle position");
  Eigen::Matrix2d J;
  J << d.x() / r, d.y() / r, -d.y() / q, d.x() / q;  // ∂h/∂m
  if (H_m) *H_m = J;
  if (H_x) {
    H_x->leftCols<2>() = -J;
    H_x->col(2) << 0, -1;
  }
}

Eigen::Vector2d RangeBearingModel::inverse(const Eigen::Vector3d& p, const RangeBearing& z,
                                           Eigen::Matrix<double, 2, 3>* G_x,
                                           Eigen::Matrix2d* G_z) const {
  const double a = p.z() + z.bearing, c = std::cos(a), s = std::sin(a);
  if (G_x) *G_x << 1, 0, -z.range * s, 0, 1, z.range * c;
  if (G_z) *G_z << c, -z.range * s, s, z.range * c;
  return p.head<2>() + z.range * Eigen::Vector2d(c, s);
}

Eigen::Vector2d RangeBearingModel::innovation(const RangeBearing& z,
                                              const Eigen::Vector2d& predicted) {
  return {z.range - predicted.x(), wrap_angle(z.bearing - predicted.y())};
}

Eigen::Matrix2d RangeBearingModel::noise() const {
  return Eigen::Vector2d(sigma_range_ * sigma_range_, sigma_bearing_ * sigma_bearing_).asDiagonal();
}

}  // namespace slamkit
