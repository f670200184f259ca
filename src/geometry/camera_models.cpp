#include "slamkit/geometry/camera_models.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace slamkit {
namespace {

constexpr int kMaxNewtonIterations = 30;
constexpr double kNewtonTolerance = 1e-12;  // in normalized coordinates / radians

bool finite(const Eigen::Vector3d& p) { return p.allFinite(); }

void check_positive(double v, const char* what) {
  if (!std::isfinite(v) || v <= 0.0) throw std::invalid_argument(std::string("camera: ") + what + " must be > 0");
}
void check_finite(double v, const char* what) {
  if (!std::isfinite(v)) throw std::invalid_argument(std::string("camera: ") + what + " is not finite");
}

}  // namespace

CameraModel::CameraModel(int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: resolution must be positive");
}

// ---- pinhole ----

PinholeCamera::PinholeCamera(double fx, double fy, double cx, double cy, int width, int height)
    : CameraModel(width, height), fx_(fx), fy_(fy), cx_(cx), cy_(cy) {
  check_positive(fx, "fx");
  check_positive(fy, "fy");
  check_finite(cx, "cx");
  check_finite(cy, "cy");
}

Eigen::VectorXd PinholeCamera::intrinsics() const { return Eigen::Vector4d(fx_, fy_, cx_, cy_); }

std::shared_ptr<CameraModel> PinholeCamera::with_intrinsics(const Eigen::VectorXd& k) const {
  if (k.size() != 4) throw std::invalid_argument("pinhole camera: 4 intrinsics expected");
  return std::make_shared<PinholeCamera>(k(0), k(1), k(2), k(3), width_, height_);
}

bool PinholeCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p,
                            Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics) const {
  if (!finite(p) || p.z() <= 1e-9) return false;
  const double iz = 1.0 / p.z(), x = p.x() * iz, y = p.y() * iz;
  *uv = Eigen::Vector2d(fx_ * x + cx_, fy_ * y + cy_);
  if (J_uv_p) *J_uv_p << fx_ * iz, 0.0, -fx_ * x * iz, 0.0, fy_ * iz, -fy_ * y * iz;
  if (J_uv_intrinsics) {
    J_uv_intrinsics->setZero(2, 4);
    (*J_uv_intrinsics)(0, 0) = x, (*J_uv_intrinsics)(1, 1) = y;
    (*J_uv_intrinsics)(0, 2) = 1.0, (*J_uv_intrinsics)(1, 3) = 1.0;
  }
  return true;
}

bool PinholeCamera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const {
  if (!uv.allFinite()) return false;
  *bearing = Eigen::Vector3d((uv.x() - cx_) / fx_, (uv.y() - cy_) / fy_, 1.0).normalized();
  return true;
}

// ---- radial-tangential ----

RadTanCamera::RadTanCamera(double fx, double fy, double cx, double cy, double k1, double k2, double p1, double p2,
                           int width, int height)
    : PinholeCamera(fx, fy, cx, cy, width, height), k1_(k1), k2_(k2), p1_(p1), p2_(p2) {
  check_finite(k1, "k1"), check_finite(k2, "k2"), check_finite(p1, "p1"), check_finite(p2, "p2");
}

Eigen::VectorXd RadTanCamera::intrinsics() const {
  Eigen::VectorXd k(8);
  k << fx_, fy_, cx_, cy_, k1_, k2_, p1_, p2_;
  return k;
}

std::shared_ptr<CameraModel> RadTanCamera::with_intrinsics(const Eigen::VectorXd& k) const {
  if (k.size() != 8) throw std::invalid_argument("radtan camera: 8 intrinsics expected");
  return std::make_shared<RadTanCamera>(k(0), k(1), k(2), k(3), k(4), k(5), k(6), k(7), width_, height_);
}

Eigen::Vector2d RadTanCamera::distort(const Eigen::Vector2d& m, Eigen::Matrix2d* J_d_m) const {
  const double x = m.x(), y = m.y(), r2 = x * x + y * y;
  const double radial = 1.0 + k1_ * r2 + k2_ * r2 * r2;
  const Eigen::Vector2d d(x * radial + 2.0 * p1_ * x * y + p2_ * (r2 + 2.0 * x * x),
                          y * radial + p1_ * (r2 + 2.0 * y * y) + 2.0 * p2_ * x * y);
  if (J_d_m) {
    const double dradial_dr2 = k1_ + 2.0 * k2_ * r2;  // ∂radial/∂x = 2x · dradial_dr2
    (*J_d_m)(0, 0) = radial + 2.0 * x * x * dradial_dr2 + 2.0 * p1_ * y + 6.0 * p2_ * x;
    (*J_d_m)(0, 1) = 2.0 * x * y * dradial_dr2 + 2.0 * p1_ * x + 2.0 * p2_ * y;
    (*J_d_m)(1, 0) = 2.0 * x * y * dradial_dr2 + 2.0 * p1_ * x + 2.0 * p2_ * y;
    (*J_d_m)(1, 1) = radial + 2.0 * y * y * dradial_dr2 + 6.0 * p1_ * y + 2.0 * p2_ * x;
  }
  return d;
}

bool RadTanCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p,
                           Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics) const {
  if (!finite(p) || p.z() <= 1e-9) return false;
  const double iz = 1.0 / p.z();
  const Eigen::Vector2d m(p.x() * iz, p.y() * iz);
  Eigen::Matrix2d J_d_m;
  const Eigen::Vector2d d = distort(m, &J_d_m);
  if (!d.allFinite()) return false;
  *uv = Eigen::Vector2d(fx_ * d.x() + cx_, fy_ * d.y() + cy_);
  if (J_uv_p) {
    Eigen::Matrix<double, 2, 3> J_m_p;
    J_m_p << iz, 0.0, -m.x() * iz, 0.0, iz, -m.y() * iz;
    const Eigen::Matrix2d K = Eigen::Vector2d(fx_, fy_).asDiagonal();
    *J_uv_p = K * J_d_m * J_m_p;
  }
  if (J_uv_intrinsics) {
    const double x = m.x(), y = m.y(), r2 = x * x + y * y;
    J_uv_intrinsics->setZero(2, 8);
    auto& J = *J_uv_intrinsics;
    J(0, 0) = d.x(), J(1, 1) = d.y(), J(0, 2) = 1.0, J(1, 3) = 1.0;
    J(0, 4) = fx_ * x * r2, J(1, 4) = fy_ * y * r2;
    J(0, 5) = fx_ * x * r2 * r2, J(1, 5) = fy_ * y * r2 * r2;
    J(0, 6) = fx_ * 2.0 * x * y, J(1, 6) = fy_ * (r2 + 2.0 * y * y);
    J(0, 7) = fx_ * (r2 + 2.0 * x * x), J(1, 7) = fy_ * 2.0 * x * y;
  }
  return true;
}

bool RadTanCamera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const {
  if (!uv.allFinite()) return false;
  const Eigen::Vector2d target((uv.x() - cx_) / fx_, (uv.y() - cy_) / fy_);
  // Newton on distort(m) = target, from m = target.
  Eigen::Vector2d m = target;
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d r = distort(m, &J) - target;
    if (r.norm() < kNewtonTolerance) {
      *bearing = Eigen::Vector3d(m.x(), m.y(), 1.0).normalized();
      return true;
    }
    const double det = J.determinant();
    if (!std::isfinite(det) || std::abs(det) < 1e-12) return false;
    m -= J.inverse() * r;
    if (!m.allFinite()) return false;
  }
  return false;
}

// ---- equidistant (Kannala-Brandt) ----

EquidistantCamera::EquidistantCamera(double fx, double fy, double cx, double cy, double k1, double k2, double k3,
                                     double k4, int width, int height)
    : PinholeCamera(fx, fy, cx, cy, width, height), k1_(k1), k2_(k2), k3_(k3), k4_(k4) {
  check_finite(k1, "k1"), check_finite(k2, "k2"), check_finite(k3, "k3"), check_finite(k4, "k4");
  // The model is invertible while θ_d(θ) increases: scan [0, π] for the first turning point.
  constexpr int kSteps = 3600;
  max_theta_ = M_PI;
  for (int i = 1; i <= kSteps; ++i) {
    const double theta = M_PI * i / kSteps;
    double slope = 0.0;
    theta_d(theta, &slope);
    if (slope <= 0.0) {
      max_theta_ = M_PI * (i - 1) / kSteps;
      break;
    }
  }
  max_theta_d_ = theta_d(max_theta_);
}

Eigen::VectorXd EquidistantCamera::intrinsics() const {
  Eigen::VectorXd k(8);
  k << fx_, fy_, cx_, cy_, k1_, k2_, k3_, k4_;
  return k;
}

std::shared_ptr<CameraModel> EquidistantCamera::with_intrinsics(const Eigen::VectorXd& k) const {
  if (k.size() != 8) throw std::invalid_argument("equidistant camera: 8 intrinsics expected");
  return std::make_shared<EquidistantCamera>(k(0), k(1), k(2), k(3), k(4), k(5), k(6), k(7), width_, height_);
}

double EquidistantCamera::theta_d(double theta, double* dthetad_dtheta) const {
  const double t2 = theta * theta, t4 = t2 * t2, t6 = t4 * t2, t8 = t4 * t4;
  if (dthetad_dtheta) *dthetad_dtheta = 1.0 + 3.0 * k1_ * t2 + 5.0 * k2_ * t4 + 7.0 * k3_ * t6 + 9.0 * k4_ * t8;
  return theta * (1.0 + k1_ * t2 + k2_ * t4 + k3_ * t6 + k4_ * t8);
}

bool EquidistantCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p,
                                Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics) const {
  if (!finite(p)) return false;
  const double a = p.x(), b = p.y(), c = p.z();
  const double rho2 = a * a + b * b, rho = std::sqrt(rho2), n2 = rho2 + c * c;
  if (n2 <= 1e-18) return false;
  const double theta = std::atan2(rho, c);
  if (theta > max_theta_) return false;
  double dtd = 0.0;
  const double td = theta_d(theta, &dtd);
  // s = θ_d / ρ; near the axis (ρ ≪ c) s → 1/c and the model is the pinhole one to first order.
  const bool on_axis = rho < 1e-10 * std::abs(c);
  if (on_axis && c <= 0.0) return false;
  const double s = on_axis ? 1.0 / c : td / rho;
  *uv = Eigen::Vector2d(fx_ * s * a + cx_, fy_ * s * b + cy_);
  if (J_uv_p) {
    if (on_axis) {
      *J_uv_p << fx_ / c, 0.0, -fx_ * a / (c * c), 0.0, fy_ / c, -fy_ * b / (c * c);
    } else {
      // ∂θ/∂(a, b, c) = (c a/ρ, c b/ρ, −ρ) / n², ∂ρ/∂(a, b, c) = (a, b, 0)/ρ,
      // ∂s = (θ_d' ∂θ − s ∂ρ) / ρ, ∂u = fx (s e_a + a ∂s), ∂v = fy (s e_b + b ∂s).
      const Eigen::Vector3d dtheta(c * a / (rho * n2), c * b / (rho * n2), -rho / n2);
      const Eigen::Vector3d drho(a / rho, b / rho, 0.0);
      const Eigen::Vector3d ds = (dtd * dtheta - s * drho) / rho;
      J_uv_p->row(0) = fx_ * (a * ds.transpose() + Eigen::RowVector3d(s, 0.0, 0.0));
      J_uv_p->row(1) = fy_ * (b * ds.transpose() + Eigen::RowVector3d(0.0, s, 0.0));
    }
  }
  if (J_uv_intrinsics) {
    J_uv_intrinsics->setZero(2, 8);
    auto& J = *J_uv_intrinsics;
    J(0, 0) = s * a, J(1, 1) = s * b, J(0, 2) = 1.0, J(1, 3) = 1.0;
    // ∂θ_d/∂k_i = θ^(2i+1); the direction factor is (a, b)/ρ (→ (a, b)/(c θ) on the axis).
    const double dir = on_axis ? 1.0 / c : 1.0 / rho;
    double power = theta * theta * theta;
    for (int i = 0; i < 4; ++i, power *= theta * theta) {
      const double scale = on_axis ? power / std::max(theta, 1e-300) : power;
      J(0, 4 + i) = fx_ * scale * dir * a;
      J(1, 4 + i) = fy_ * scale * dir * b;
    }
  }
  return uv->allFinite();
}

bool EquidistantCamera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const {
  if (!uv.allFinite()) return false;
  const double mx = (uv.x() - cx_) / fx_, my = (uv.y() - cy_) / fy_;
  const double td = std::hypot(mx, my);
  if (td < 1e-15) {
    *bearing = Eigen::Vector3d(0.0, 0.0, 1.0);
    return true;
  }
  if (td > max_theta_d_) return false;
  // Newton on θ_d(θ) = td from θ = td (θ_d is increasing on [0, max_theta]).
  double theta = std::min(td, max_theta_);
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    double slope = 0.0;
    const double r = theta_d(theta, &slope) - td;
    if (std::abs(r) < kNewtonTolerance) {
      const double st = std::sin(theta);
      *bearing = Eigen::Vector3d(st * mx / td, st * my / td, std::cos(theta));
      return true;
    }
    if (!(slope > 0.0)) return false;
    theta = std::clamp(theta - r / slope, 0.0, max_theta_);
  }
  return false;
}

std::shared_ptr<CameraModel> make_camera_model(const std::string& model, const std::vector<double>& k, int width,
                                               int height) {
  const auto need = [&](std::size_t n) {
    if (k.size() != n)
      throw std::invalid_argument("camera model '" + model + "' needs " + std::to_string(n) + " intrinsics, got " +
                                  std::to_string(k.size()));
  };
  if (model == "pinhole" || model == "none") {
    need(4);
    return std::make_shared<PinholeCamera>(k[0], k[1], k[2], k[3], width, height);
  }
  if (model == "radtan") {
    need(8);
    return std::make_shared<RadTanCamera>(k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], width, height);
  }
  if (model == "equidistant") {
    need(8);
    return std::make_shared<EquidistantCamera>(k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7], width, height);
  }
  throw std::invalid_argument("unknown camera model '" + model + "' (pinhole, radtan, equidistant)");
}

}  // namespace slamkit
