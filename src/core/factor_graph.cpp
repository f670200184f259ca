#include "slamkit/core/factor_graph.h"

#include <cmath>

#include "slamkit/core/error.h"

namespace slamkit {

void FactorGraph::check_against(const Values& values) const {
  for (std::size_t f = 0; f < factors_.size(); ++f) {
    const Factor& factor = *factors_[f];
    for (std::size_t k = 0; k < factor.keys().size(); ++k) {
      const Key key = factor.keys()[k];
      if (!values.exists(key))
        throw InputError("", 0, "key", "factor " + std::to_string(f) + " uses variable " + key_to_string(key) +
                                           ", which has no value");
      const Manifold& have = values.manifold(values.index_of(key));
      const Manifold& want = factor.variable_manifold(k);
      if (&have != &want)
        throw InputError("", 0, "key", "factor " + std::to_string(f) + " expects variable " + key_to_string(key) +
                                           " to be a " + want.name() + ", but it is a " + have.name());
    }
  }
}

double FactorGraph::cost(const Values& values) const {
  check_against(values);
  double total = 0.0;
  std::vector<const double*> params;
  std::vector<double> residual;
  for (std::size_t f = 0; f < factors_.size(); ++f) {
    const Factor& factor = *factors_[f];
    params.clear();
    for (Key k : factor.keys()) params.push_back(values.params(values.index_of(k)));
    residual.resize(factor.residual_dim());
    const double c = factor.cost(params.data(), residual.data());
    if (!std::isfinite(c)) throw NumericalError("factor " + std::to_string(f) + " evaluates to a non-finite cost");
    total += c;
  }
  return total;
}

}  // namespace slamkit
