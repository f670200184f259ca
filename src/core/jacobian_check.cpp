#include "slamkit/core/jacobian_check.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace slamkit {

std::string JacobianCheckResult::message() const {
  std::ostringstream os;
  os << (ok ? "Jacobians OK" : "Jacobian MISMATCH") << " (" << factors_checked << " factors): worst relative error "
     << worst_error << " at factor " << factor << ", variable " << variable << ", entry (" << row << "," << col
     << "): analytic " << analytic << ", numeric " << numeric;
  return os.str();
}

JacobianCheckResult check_jacobians(const FactorGraph& graph, const Values& values, double tolerance, double step) {
  graph.check_against(values);
  JacobianCheckResult out;
  out.worst_error = 0.0;
  for (std::size_t f = 0; f < graph.size(); ++f) {
    const Factor& factor = graph[f];
    const int m = factor.residual_dim();
    const std::size_t k = factor.keys().size();
    std::vector<std::vector<double>> params(k);
    for (std::size_t v = 0; v < k; ++v) {
      const std::size_t i = values.index_of(factor.keys()[v]);
      params[v].assign(values.params(i), values.params(i) + values.manifold(i).ambient_dim());
    }
    std::vector<const double*> ptrs(k);
    for (std::size_t v = 0; v < k; ++v) ptrs[v] = params[v].data();
    std::vector<std::vector<double>> jac(k);
    std::vector<double*> jptrs(k);
    for (std::size_t v = 0; v < k; ++v) {
      jac[v].resize(static_cast<std::size_t>(m) * factor.variable_manifold(v).tangent_dim());
      jptrs[v] = jac[v].data();
    }
    std::vector<double> r0(m), rp(m), rm(m);
    factor.evaluate(ptrs.data(), r0.data(), jptrs.data());
    ++out.factors_checked;
    for (std::size_t v = 0; v < k; ++v) {
      const Manifold& man = factor.variable_manifold(v);
      const int d = man.tangent_dim();
      const std::vector<double> x0 = params[v];
      std::vector<double> delta(d, 0.0);
      for (int c = 0; c < d; ++c) {
        delta[c] = step;
        man.plus(x0.data(), delta.data(), params[v].data());
        factor.evaluate(ptrs.data(), rp.data(), nullptr);
        delta[c] = -step;
        man.plus(x0.data(), delta.data(), params[v].data());
        factor.evaluate(ptrs.data(), rm.data(), nullptr);
        delta[c] = 0.0;
        params[v] = x0;
        for (int r = 0; r < m; ++r) {
          const double numeric = (rp[r] - rm[r]) / (2.0 * step);
          const double analytic = jac[v][static_cast<std::size_t>(c) * m + r];
          double err = std::abs(analytic - numeric) / std::max(1.0, std::abs(numeric));
          if (!std::isfinite(err)) err = std::numeric_limits<double>::infinity();
          if (err > out.worst_error || (f == 0 && v == 0 && c == 0 && r == 0)) {
            out.worst_error = err, out.factor = f, out.variable = v, out.row = r, out.col = c;
            out.analytic = analytic, out.numeric = numeric;
          }
        }
      }
    }
  }
  out.ok = out.worst_error <= tolerance;
  return out;
}

}  // namespace slamkit
