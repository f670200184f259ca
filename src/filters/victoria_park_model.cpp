#include "slamkit/filters/victoria_park_model.h"

#include <cmath>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {

VictoriaParkModel::VictoriaParkModel(const VictoriaParkGeometry& g, double sigma_v, double sigma_steer)
    : geometry_(g), sigma_v_(sigma_v), sigma_steer_(sigma_steer) {
  if (!(g.L > 0) || !std::isfinite(g.L)) throw InputError("victoria_park model", 0, "L", "wheelbase must be positive");
  if (!std::isfinite(g.a) || !std::isfinite(g.b) || !std::isfinite(g.H))
    throw InputError("victoria_park model", 0, "a/b/H", "must be finite");
  if (!(sigma_v >= 0) || !(sigma_steer >= 0) || !std::isfinite(sigma_v) || !std::isfinite(sigma_steer))
    throw InputError("victoria_park model", 0, "sigma", "noise must be non-negative and finite");
}

Eigen::Vector3d VictoriaParkModel::predict(const Eigen::Vector3d& p, const Control& u) const {
  const auto& g = geometry_;
  const double t = std::tan(u.turn), vc = u.v / (1 - t * g.H / g.L), w = vc * t / g.L;
  const double c = std::cos(p.z()), s = std::sin(p.z());
  return {p.x() + u.dt * (vc * c - w * (g.a * s + g.b * c)),
          p.y() + u.dt * (vc * s + w * (g.a * c - g.b * s)), wrap_angle(p.z() + u.dt * w)};
}

void VictoriaParkModel::jacobians(const Eigen::Vector3d& p, const Control& u, Eigen::Matrix3d* F_x,
                                  Eigen::Matrix<double, 3, 2>* F_u) const {
  const auto& g = geometry_;
  const double t = std::tan(u.turn), den = 1 - t * g.H / g.L;
  const double vc = u.v / den, w = vc * t / g.L;
  const double c = std::cos(p.z()), s = std::sin(p.z());
  if (F_x)
    *F_x << 1, 0, u.dt * (-vc * s - w * (g.a * c - g.b * s)),  //
        0, 1, u.dt * (vc * c - w * (g.a * s + g.b * c)),       //
        0, 0, 1;
  if (F_u) {
    // ∂vc/∂v = 1/den, ∂vc/∂α = v (1 + t²) H / (L den²); ∂w/∂· = (∂vc t + vc ∂t) / L.
    const double sec2 = 1 + t * t;
    const double dvc_dv = 1 / den, dvc_da = u.v * sec2 * g.H / (g.L * den * den);
    const double dw_dv = dvc_dv * t / g.L, dw_da = (dvc_da * t + vc * sec2) / g.L;
    const double px = c, qx = -(g.a * s + g.b * c), py = s, qy = g.a * c - g.b * s;
    *F_u << u.dt * (px * dvc_dv + qx * dw_dv), u.dt * (px * dvc_da + qx * dw_da),  //
        u.dt * (py * dvc_dv + qy * dw_dv), u.dt * (py * dvc_da + qy * dw_da),      //
        u.dt * dw_dv, u.dt * dw_da;
  }
}

Eigen::Matrix2d VictoriaParkModel::control_noise(const Control&) const {
  return Eigen::Vector2d(sigma_v_ * sigma_v_, sigma_steer_ * sigma_steer_).asDiagonal();
}

}  // namespace slamkit
