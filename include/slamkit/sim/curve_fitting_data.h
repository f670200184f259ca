// Samples for the textbook curve fit y = exp(a x² + b x + c) + w: n points x_i = i/n on [0, 1),
// w ~ N(0, σ²) from std::mt19937 with the given seed and std::normal_distribution (libstdc++:
// deterministic for a seed). Defaults: truth (1, 2, 1), σ = 1, 100 points.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

namespace slamkit {

struct CurveFittingData {
  std::vector<double> x, y;
  Eigen::Vector3d truth;
  double sigma = 1.0;
};

inline CurveFittingData generate_curve_fitting_data(std::uint32_t seed = 1, int n = 100,
                                                    const Eigen::Vector3d& truth = Eigen::Vector3d(1, 2, 1),
                                                    double sigma = 1.0) {
  CurveFittingData d;
  d.truth = truth;
  d.sigma = sigma;
  std::mt19937 rng(seed);
  std::normal_distribution<double> w(0.0, sigma);
  for (int i = 0; i < n; ++i) {
    const double x = static_cast<double>(i) / n;
    d.x.push_back(x);
    d.y.push_back(std::exp(truth[0] * x * x + truth[1] * x + truth[2]) + w(rng));
  }
  return d;
}

}  // namespace slamkit
