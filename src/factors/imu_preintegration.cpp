#include "slamkit/factors/imu_preintegration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

// Block offsets of the error state [δφ, δv, δp, δb_g, δb_a].
constexpr int kR = 0, kV = 3, kP = 6, kBg = 9, kBa = 12;

void check_noise(const ImuNoise& n) {
  for (double x : {n.gyro_noise_density, n.accel_noise_density, n.gyro_random_walk, n.accel_random_walk})
    if (!(std::isfinite(x) && x > 0.0)) throw std::invalid_argument("ImuNoise: every density must be finite and > 0");
}

ImuMeasurement lerp(const ImuMeasurement& a, const ImuMeasurement& b, double t) {
  const double s = (t - a.stamp) / (b.stamp - a.stamp);
  ImuMeasurement m;
  m.stamp = t;
  m.gyro = (1.0 - s) * a.gyro + s * b.gyro;
  m.accel = (1.0 - s) * a.accel + s * b.accel;
  return m;
}

}  // namespace

ImuPreintegration::ImuPreintegration(const ImuBias& linearization_bias, const ImuNoise& noise)
    : bias_(linearization_bias), noise_(noise) {
  check_noise(noise_);
}

void ImuPreintegration::reset(const ImuBias& linearization_bias) {
  *this = ImuPreintegration(linearization_bias, noise_);
}

void ImuPreintegration::integrate(double dt, const Eigen::Vector3d& gyro0, const Eigen::Vector3d& accel0,
                                  const Eigen::Vector3d& gyro1, const Eigen::Vector3d& accel1) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::invalid_argument("ImuPreintegration: dt must be finite and > 0");
  using M3 = Eigen::Matrix3d;
  const Eigen::Vector3d w = 0.5 * (gyro0 + gyro1) - bias_.gyro;
  const Eigen::Vector3d wdt = w * dt;
  const SO3 step = SO3::exp(wdt);
  const M3 dRs = step.matrix();
  const M3 Jr = SO3::right_jacobian(wdt);
  const M3 R0 = dR_.matrix();
  const SO3 R1_so3 = dR_ * step;
  const M3 R1 = R1_so3.matrix();
  const Eigen::Vector3d a0 = accel0 - bias_.accel, a1 = accel1 - bias_.accel;
  const Eigen::Vector3d a_mid = 0.5 * (R0 * a0 + R1 * a1);

  // Perturbation of ā: dā = Aφ δφ_k + Abg (δb_g + n_g) + Aba (δb_a + n_a).
  const M3 A_phi = -0.5 * (R0 * skew(a0) + R1 * skew(a1) * dRs.transpose());
  const M3 A_bg = 0.5 * R1 * skew(a1) * Jr * dt;
  const M3 A_ba = -0.5 * (R0 + R1);

  Matrix15 F = Matrix15::Identity();
  F.block<3, 3>(kR, kR) = dRs.transpose();
  F.block<3, 3>(kR, kBg) = -Jr * dt;
  F.block<3, 3>(kV, kR) = dt * A_phi;
  F.block<3, 3>(kV, kBg) = dt * A_bg;
  F.block<3, 3>(kV, kBa) = dt * A_ba;
  F.block<3, 3>(kP, kR) = 0.5 * dt * dt * A_phi;
  F.block<3, 3>(kP, kV) = dt * M3::Identity();
  F.block<3, 3>(kP, kBg) = 0.5 * dt * dt * A_bg;
  F.block<3, 3>(kP, kBa) = 0.5 * dt * dt * A_ba;

  // Noise input G for n = [n_g, n_a, n_bg, n_ba] and its discrete covariance Q_d.
  Eigen::Matrix<double, 15, 12> G = Eigen::Matrix<double, 15, 12>::Zero();
  G.block<3, 3>(kR, 0) = -Jr * dt;
  G.block<3, 3>(kV, 0) = dt * A_bg;
  G.block<3, 3>(kV, 3) = dt * A_ba;
  G.block<3, 3>(kP, 0) = 0.5 * dt * dt * A_bg;
  G.block<3, 3>(kP, 3) = 0.5 * dt * dt * A_ba;
  G.block<3, 3>(kBg, 6).setIdentity();
  G.block<3, 3>(kBa, 9).setIdentity();
  Eigen::Matrix<double, 12, 1> q;
  q << Eigen::Vector3d::Constant(noise_.gyro_noise_density * noise_.gyro_noise_density / dt),
      Eigen::Vector3d::Constant(noise_.accel_noise_density * noise_.accel_noise_density / dt),
      Eigen::Vector3d::Constant(noise_.gyro_random_walk * noise_.gyro_random_walk * dt),
      Eigen::Vector3d::Constant(noise_.accel_random_walk * noise_.accel_random_walk * dt);

  P_ = F * P_ * F.transpose() + G * q.asDiagonal() * G.transpose();
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  J_ = F * J_;

  dp_ += dv_ * dt + 0.5 * a_mid * dt * dt;
  dv_ += a_mid * dt;
  dR_ = R1_so3;
  dt_ += dt;
}

void ImuPreintegration::integrate_between(const std::vector<ImuMeasurement>& samples, double t0, double t1) {
  if (!(t1 > t0)) throw std::invalid_argument("ImuPreintegration::integrate_between: t1 must be after t0");
  if (samples.size() < 2 || samples.front().stamp > t0 || samples.back().stamp < t1)
    throw std::invalid_argument("ImuPreintegration::integrate_between: the IMU samples do not cover [" +
                                std::to_string(t0) + ", " + std::to_string(t1) + "]");
  const auto by_stamp = [](const ImuMeasurement& m, double t) { return m.stamp < t; };
  // First sample with stamp > t0 (at least index 1, since samples[0].stamp ≤ t0).
  auto it = std::upper_bound(samples.begin(), samples.end(), t0,
                             [](double t, const ImuMeasurement& m) { return t < m.stamp; });
  const auto end = std::lower_bound(samples.begin(), samples.end(), t1, by_stamp);  // first ≥ t1
  ImuMeasurement prev = lerp(*(it - 1), *it, t0);
  for (; it < end; ++it) {
    if (it->stamp > prev.stamp) integrate(it->stamp - prev.stamp, prev.gyro, prev.accel, it->gyro, it->accel);
    prev = *it;
  }
  const ImuMeasurement last = end->stamp == t1 ? *end : lerp(*(end - 1), *end, t1);
  if (last.stamp > prev.stamp) integrate(last.stamp - prev.stamp, prev.gyro, prev.accel, last.gyro, last.accel);
}

SO3 ImuPreintegration::delta_R(const ImuBias& b) const {
  return dR_ * SO3::exp(J_.block<3, 3>(kR, kBg) * (b.gyro - bias_.gyro));
}
Eigen::Vector3d ImuPreintegration::delta_v(const ImuBias& b) const {
  return dv_ + J_.block<3, 3>(kV, kBg) * (b.gyro - bias_.gyro) + J_.block<3, 3>(kV, kBa) * (b.accel - bias_.accel);
}
Eigen::Vector3d ImuPreintegration::delta_p(const ImuBias& b) const {
  return dp_ + J_.block<3, 3>(kP, kBg) * (b.gyro - bias_.gyro) + J_.block<3, 3>(kP, kBa) * (b.accel - bias_.accel);
}

ImuState ImuPreintegration::predict(const ImuState& xi, const Eigen::Vector3d& g) const {
  const ImuBias b{xi.bg, xi.ba};
  ImuState xj = xi;
  xj.R = xi.R * delta_R(b);
  xj.v = xi.v + g * dt_ + xi.R.act(delta_v(b));
  xj.p = xi.p + xi.v * dt_ + 0.5 * g * dt_ * dt_ + xi.R.act(delta_p(b));
  return xj;
}

ImuFactor::ImuFactor(Key state_i, Key state_j, ImuPreintegration preintegration, const Eigen::Vector3d& g_world)
    : FactorN({state_i, state_j}, NoiseModel::covariance(preintegration.covariance())),
      pim_(std::move(preintegration)),
      g_(g_world) {}

ImuFactor::Residual ImuFactor::error(const ImuState& xi, const ImuState& xj, Jacobian<ImuState>* J_i,
                                     Jacobian<ImuState>* J_j) const {
  using M3 = Eigen::Matrix3d;
  const double T = pim_.dt();
  const ImuBias b{xi.bg, xi.ba};
  const Eigen::Vector3d dbg = xi.bg - pim_.linearization_bias().gyro;
  const ImuPreintegration::Matrix96 Jb = pim_.bias_jacobian();
  const Eigen::Vector3d phi_b = Jb.block<3, 3>(0, 0) * dbg;
  const SO3 dR = pim_.delta_R() * SO3::exp(phi_b);
  const M3 RiT = xi.R.matrix().transpose();
  const Eigen::Vector3d dv_world = xj.v - xi.v - g_ * T;
  const Eigen::Vector3d dp_world = xj.p - xi.p - xi.v * T - 0.5 * g_ * T * T;

  Residual r;
  const SO3 E = dR.inverse() * xi.R.inverse() * xj.R;
  const Eigen::Vector3d rR = E.log();
  r.segment<3>(kR) = rR;
  r.segment<3>(kV) = RiT * dv_world - pim_.delta_v(b);
  r.segment<3>(kP) = RiT * dp_world - pim_.delta_p(b);
  r.segment<3>(kBg) = xj.bg - xi.bg;
  r.segment<3>(kBa) = xj.ba - xi.ba;

  if (J_i || J_j) {
    const M3 Jr_inv = SO3::right_jacobian_inverse(rR);
    if (J_i) {
      Jacobian<ImuState>& J = *J_i;
      J.setZero();
      J.block<3, 3>(kR, kR) = -Jr_inv * (xj.R.matrix().transpose() * xi.R.matrix());
      J.block<3, 3>(kR, kBg) = -Jr_inv * E.matrix().transpose() * SO3::right_jacobian(phi_b) * Jb.block<3, 3>(0, 0);
      J.block<3, 3>(kV, kR) = skew(RiT * dv_world);
      J.block<3, 3>(kV, kV) = -RiT;
      J.block<3, 3>(kV, kBg) = -Jb.block<3, 3>(3, 0);
      J.block<3, 3>(kV, kBa) = -Jb.block<3, 3>(3, 3);
      J.block<3, 3>(kP, kR) = skew(RiT * dp_world);
      J.block<3, 3>(kP, kV) = -RiT * T;
      J.block<3, 3>(kP, kP) = -RiT;
      J.block<3, 3>(kP, kBg) = -Jb.block<3, 3>(6, 0);
      J.block<3, 3>(kP, kBa) = -Jb.block<3, 3>(6, 3);
      J.block<3, 3>(kBg, kBg) = -M3::Identity();
      J.block<3, 3>(kBa, kBa) = -M3::Identity();
    }
    if (J_j) {
      Jacobian<ImuState>& J = *J_j;
      J.setZero();
      J.block<3, 3>(kR, kR) = Jr_inv;
      J.block<3, 3>(kV, kV) = RiT;
      J.block<3, 3>(kP, kP) = RiT;
      J.block<3, 3>(kBg, kBg).setIdentity();
      J.block<3, 3>(kBa, kBa).setIdentity();
    }
  }
  return r;
}

}  // namespace slamkit
