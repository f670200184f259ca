// FactorGraph: the factors of a problem. The cost of Values x is Σ_f ρ_f(‖R_f r_f(x)‖²)
// (g2o's chi2 when no kernel is set). Holds shared ownership of immutable factors.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "slamkit/core/factor.h"
#include "slamkit/core/values.h"

namespace slamkit {

class FactorGraph {
 public:
  void add(std::shared_ptr<const Factor> f) { factors_.push_back(std::move(f)); }
  template <class F, class... Args>
  std::shared_ptr<F> emplace(Args&&... args) {
    auto f = std::make_shared<F>(std::forward<Args>(args)...);
    factors_.push_back(f);
    return f;
  }
  void reserve(std::size_t n) { factors_.reserve(n); }
  std::size_t size() const { return factors_.size(); }
  bool empty() const { return factors_.empty(); }
  const Factor& operator[](std::size_t i) const { return *factors_[i]; }
  const std::shared_ptr<const Factor>& factor(std::size_t i) const { return factors_[i]; }
  auto begin() const { return factors_.begin(); }
  auto end() const { return factors_.end(); }

  /// Total cost at `values`; throws InputError on a missing or mistyped variable and
  /// NumericalError if a factor does not evaluate to a finite number.
  double cost(const Values& values) const;

  /// Checks that every key exists in `values` with the manifold the factor expects.
  void check_against(const Values& values) const;

 private:
  std::vector<std::shared_ptr<const Factor>> factors_;
};

}  // namespace slamkit
