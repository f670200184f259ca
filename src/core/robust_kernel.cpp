#include "slamkit/core/robust_kernel.h"

#include <cmath>

#include "slamkit/core/error.h"

namespace slamkit {

RobustKernel::RobustKernel(double delta) : delta_(delta), delta2_(delta * delta) {
  if (!(delta > 0.0) || !std::isfinite(delta))
    throw InputError("", 0, "delta", "robust kernel scale must be positive and finite");
}

void HuberKernel::evaluate(double s, double rho[3]) const {
  if (s <= delta2_) {
    rho[0] = s, rho[1] = 1.0, rho[2] = 0.0;
    return;
  }
  const double r = std::sqrt(s);
  rho[0] = 2.0 * delta_ * r - delta2_;
  rho[1] = delta_ / r;
  rho[2] = -0.5 * rho[1] / s;
}

void CauchyKernel::evaluate(double s, double rho[3]) const {
  const double inv = 1.0 / (1.0 + s / delta2_);
  rho[0] = delta2_ * std::log1p(s / delta2_);
  rho[1] = inv;
  rho[2] = -inv * inv / delta2_;
}

void TukeyKernel::evaluate(double s, double rho[3]) const {
  if (s > delta2_) {
    rho[0] = delta2_ / 3.0, rho[1] = 0.0, rho[2] = 0.0;
    return;
  }
  const double a = 1.0 - s / delta2_;
  rho[0] = delta2_ / 3.0 * (1.0 - a * a * a);
  rho[1] = a * a;
  rho[2] = -2.0 * a / delta2_;
}

void GemanMcClureKernel::evaluate(double s, double rho[3]) const {
  const double d = delta2_ + s;
  rho[0] = delta2_ * s / d;
  rho[1] = delta2_ * delta2_ / (d * d);
  rho[2] = -2.0 * rho[1] / d;
}

void DcsKernel::evaluate(double s, double rho[3]) const {
  const double phi = delta2_;
  if (s <= phi) {
    rho[0] = s, rho[1] = 1.0, rho[2] = 0.0;
    return;
  }
  const double inv = 1.0 / (phi + s);
  rho[0] = phi * (3.0 * s - phi) * inv;
  rho[1] = 4.0 * phi * phi * inv * inv;
  rho[2] = -2.0 * rho[1] * inv;
}

std::shared_ptr<const RobustKernel> make_robust_kernel(const std::string& name, double delta) {
  if (name == "huber") return std::make_shared<HuberKernel>(delta);
  if (name == "cauchy") return std::make_shared<CauchyKernel>(delta);
  if (name == "tukey") return std::make_shared<TukeyKernel>(delta);
  if (name == "geman-mcclure" || name == "gm") return std::make_shared<GemanMcClureKernel>(delta);
  if (name == "dcs") return std::make_shared<DcsKernel>(delta);
  throw InputError("", 0, "kernel", "unknown robust kernel '" + name +
                                        "' (huber, cauchy, tukey, geman-mcclure, dcs)");
}

std::shared_ptr<const RobustKernel> parse_robust_kernel(const std::string& spec) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos) throw InputError("", 0, "robust", "expected KERNEL:delta, got '" + spec + "'");
  const std::string number = spec.substr(colon + 1);
  std::size_t used = 0;
  double delta = 0.0;
  try {
    delta = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size())
    throw InputError("", 0, "robust", "kernel scale '" + number + "' is not a number");
  return make_robust_kernel(spec.substr(0, colon), delta);
}

}  // namespace slamkit
