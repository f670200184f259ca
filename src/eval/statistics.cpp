#include "slamkit/eval/statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace slamkit {

ErrorStatistics compute_statistics(const std::vector<double>& e) {
  if (e.empty()) throw std::invalid_argument("statistics of an empty error series");
  ErrorStatistics s;
  s.count = e.size();
  const double n = static_cast<double>(e.size());
  double sum = 0.0, sse = 0.0;
  s.min = s.max = e.front();
  for (double v : e) {
    if (!std::isfinite(v)) throw std::invalid_argument("error series holds a non-finite value");
    sum += v;
    sse += v * v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.sse = sse;
  s.mean = sum / n;
  s.rmse = std::sqrt(sse / n);
  double var = 0.0;
  for (double v : e) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);

  std::vector<double> sorted = e;
  const std::size_t mid = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid), sorted.end());
  const double upper = sorted[mid];
  if (sorted.size() % 2 == 1) {
    s.median = upper;
  } else {
    const double lower = *std::max_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid));
    s.median = 0.5 * (lower + upper);
  }
  return s;
}

}  // namespace slamkit
