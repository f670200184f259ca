// DVI weighting options (vio/sliding_window_estimator.h): α(M), θ and their text forms.
#include <cmath>
#include <cstdlib>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/vio/sliding_window_estimator.h"

namespace slamkit {
namespace {

bool parse_number(const std::string& text, double* v) {
  if (text.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*v);
}

}  // namespace

double DviOptions::theta_for(int groups) const {
  if (!adaptive_theta || groups < 0) return theta;
  return std::min(theta_max, theta + theta_per_group * groups);
}

double DviOptions::alpha_of(double m) const {
  switch (alpha) {
    case Alpha::kOne: return 1.0;
    case Alpha::kRatio: return m;
    case Alpha::kPower: return std::pow(m, alpha_power);
  }
  return 1.0;
}

void parse_dvi_alpha(const std::string& text, DviOptions* o) {
  double k = 0.0;
  if (text == "1") {
    o->alpha = DviOptions::Alpha::kOne;
  } else if (text == "M" || text == "m") {
    o->alpha = DviOptions::Alpha::kRatio;
  } else if (text.size() > 2 && (text[0] == 'M' || text[0] == 'm') && text[1] == '^' &&
             parse_number(text.substr(2), &k) && k > 0.0) {
    o->alpha = DviOptions::Alpha::kPower;
    o->alpha_power = k;
  } else {
    throw InputError("", 0, "alpha", "'" + text + "' is not an α form (1, M or M^k with k > 0)");
  }
}

void parse_dvi_theta(const std::string& text, DviOptions* o) {
  double v = 0.0;
  if (parse_number(text, &v) && v >= 0.0 && v <= 1.0) {
    o->theta = v, o->adaptive_theta = false;
    return;
  }
  if (text == "adaptive") {
    o->adaptive_theta = true;
    return;
  }
  const std::string prefix = "adaptive:";
  if (text.rfind(prefix, 0) == 0) {
    const std::string rest = text.substr(prefix.size());
    const auto c1 = rest.find(','), c2 = rest.find(',', c1 == std::string::npos ? c1 : c1 + 1);
    double base = 0.0, per = 0.0, max = 0.0;
    if (c1 != std::string::npos && c2 != std::string::npos && parse_number(rest.substr(0, c1), &base) &&
        parse_number(rest.substr(c1 + 1, c2 - c1 - 1), &per) && parse_number(rest.substr(c2 + 1), &max) &&
        base >= 0.0 && base <= 1.0 && per >= 0.0 && max >= base && max <= 1.0) {
      o->adaptive_theta = true, o->theta = base, o->theta_per_group = per, o->theta_max = max;
      return;
    }
  }
  throw InputError("", 0, "theta", "'" + text + "' is not a θ (a number in [0, 1], adaptive or adaptive:BASE,PER_GROUP,MAX)");
}

}  // namespace slamkit
