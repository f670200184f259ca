// Curve fitting: y = exp(a x² + b x + c) + w, the textbook nonlinear least-squares example.
// Truth (1, 2, 1), σ = 1, 100 points on [0, 1) generated with seed 1 (sim/curve_fitting_data.h),
// start (2, −1, 5); solved with each step strategy of the Optimizer.
#include <cstdio>

#include "slamkit/factors/exp_curve_factor.h"
#include "slamkit/sim/curve_fitting_data.h"
#include "slamkit/solvers/optimizer.h"

int main() {
  using namespace slamkit;
  const CurveFittingData data = generate_curve_fitting_data(1);
  FactorGraph graph;
  for (std::size_t i = 0; i < data.x.size(); ++i) graph.emplace<ExpCurveFactor>(Key{0}, data.x[i], data.y[i], data.sigma);
  for (Algorithm a : {Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM, Algorithm::kDogleg, Algorithm::kGaussNewton}) {
    Values v;
    v.insert(Key{0}, Eigen::Vector3d(2, -1, 5));
    OptimizerOptions o;
    o.algorithm = a;
    o.num_threads = 1;
    const Summary s = Optimizer(o).optimize(graph, v);
    const Eigen::Vector3d t = v.at<Eigen::Vector3d>(Key{0});
    std::printf("%-7s a %.6f b %.6f c %.6f  cost (1/2 sum r^2) %.6f  %d iterations, %s\n", to_string(a), t[0], t[1],
                t[2], 0.5 * s.final_cost, s.iterations, to_string(s.termination));
    if (!s.success()) return 1;
  }
  return 0;
}
