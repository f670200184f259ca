// Summary statistics of an error series, defined as evo (and numpy) define them:
//   sse = Σ e², rmse = √(sse / n), mean = Σ e / n, median = middle value (mean of the two
//   middle values for even n), std = √(Σ (e − mean)² / n) (population, ddof = 0), min, max.
#pragma once

#include <cstddef>
#include <vector>

namespace slamkit {

struct ErrorStatistics {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;
  std::size_t count = 0;
};

/// Statistics of e; throws std::invalid_argument if e is empty or holds a non-finite value.
ErrorStatistics compute_statistics(const std::vector<double>& e);

}  // namespace slamkit
