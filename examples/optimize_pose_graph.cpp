// The pose-graph pipeline from the API: a simulated 3D sphere graph with ground truth,
// chordal initialization, Gauss-Newton, and the error of the result against the truth.
#include <slamkit/slamkit.h>

#include <cmath>
#include <iostream>

int main() {
  slamkit::PoseGraphSimOptions sim;
  sim.world = "sphere";
  slamkit::PoseGraph truth;
  slamkit::PoseGraph graph = slamkit::generate_pose_graph(sim, &truth);

  slamkit::PoseGraphOptimizerOptions options;  // init auto (chordal in 3D), Gauss-Newton
  options.optimizer.callback = [&](const slamkit::IterationSummary& it) {
    std::cout << slamkit::Summary::progress_line(it, options.optimizer.algorithm) << "\n";
    return true;
  };
  std::cout << slamkit::Summary::progress_header() << "\n";
  const slamkit::PoseGraphResult result = slamkit::optimize_pose_graph(graph, options);
  std::cout << result.summary.report();

  // At the maximum-likelihood estimate chi2 follows a chi-square law with m − n degrees of
  // freedom (m residuals, n free parameters): chi2 / (m − n) ≈ 1.
  const double dof = result.summary.num_residuals - result.summary.tangent_dim;
  double worst = 0.0;
  for (std::size_t i = 0; i < graph.vertices().size(); ++i)
    worst = std::max(worst, (graph.vertices()[i].pose3.translation() - truth.vertices()[i].pose3.translation()).norm());
  std::cout << "chi2 " << result.input_chi2 << " -> " << result.final_chi2 << " (chi2/dof " << result.final_chi2 / dof
            << "), worst position error " << worst << " m\n";
  return result.summary.success() && std::abs(result.final_chi2 / dof - 1.0) < 0.1 ? 0 : 1;
}
