// Writing your own factor: 2D range-only localization. A robot at unknown position p observes
// its distance to four beacons; FactorN<1, Vector2d> gives a 1-dim residual with an analytic
// Jacobian, checked numerically before optimizing with Levenberg-Marquardt.
#include <slamkit/slamkit.h>

#include <cmath>
#include <iostream>

using slamkit::FactorN;

class RangeFactor final : public FactorN<1, Eigen::Vector2d> {
 public:
  RangeFactor(slamkit::Key key, const Eigen::Vector2d& beacon, double range, double sigma)
      : FactorN({key}, slamkit::NoiseModel::isotropic(1, sigma)), beacon_(beacon), range_(range) {}

  // e = ‖p − b‖ − range,  ∂e/∂p = (p − b)ᵀ / ‖p − b‖
  Residual error(const Eigen::Vector2d& p, Jacobian<Eigen::Vector2d>* J) const override {
    const Eigen::Vector2d d = p - beacon_;
    const double n = d.norm();
    if (J) *J = d.transpose() / n;
    return Residual(n - range_);
  }

 private:
  Eigen::Vector2d beacon_;
  double range_;
};

int main() {
  const Eigen::Vector2d truth(2.0, 3.0);
  slamkit::FactorGraph graph;
  for (const Eigen::Vector2d& b : {Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 0), Eigen::Vector2d(0, 10),
                                   Eigen::Vector2d(10, 10)})
    graph.emplace<RangeFactor>(slamkit::Key{0}, b, (truth - b).norm(), 0.1);

  slamkit::Values values;
  values.insert(slamkit::Key{0}, Eigen::Vector2d(8.0, 8.0));

  const slamkit::JacobianCheckResult check = slamkit::check_jacobians(graph, values);
  std::cout << check.message() << "\n";

  slamkit::OptimizerOptions options;
  options.algorithm = slamkit::Algorithm::kLevenbergMarquardt;
  const slamkit::Summary summary = slamkit::Optimizer(options).optimize(graph, values);
  std::cout << summary.report();
  const Eigen::Vector2d p = values.at<Eigen::Vector2d>(0);
  std::cout << "estimate " << p.transpose() << " (truth " << truth.transpose() << ")\n";
  return check.ok && (p - truth).norm() < 1e-6 ? 0 : 1;
}
