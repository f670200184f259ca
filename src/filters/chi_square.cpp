#include "slamkit/filters/chi_square.h"

#include <cmath>
#include <stdexcept>

namespace slamkit {

namespace {
// Regularized lower incomplete gamma P(a, x): series for x < a + 1, otherwise 1 − Q(a, x)
// with Q by its continued fraction (modified Lentz).
double gamma_p(double a, double x) {
  if (x <= 0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}
}  // namespace

double chi2_cdf(double x, double dof) {
  if (!(dof > 0)) throw std::invalid_argument("chi2_cdf: dof must be > 0");
  return gamma_p(0.5 * dof, 0.5 * x);
}

double chi2_quantile(double p, double dof) {
  if (!(p > 0 && p < 1) || !(dof > 0)) throw std::invalid_argument("chi2_quantile: need 0 < p < 1, dof > 0");
  double lo = 0, hi = dof + 10 * std::sqrt(2 * dof) + 10;
  while (chi2_cdf(hi, dof) < p) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_cdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace slamkit
