// Uses the installed library end to end: generate a pose graph, optimize it, check the result.
#include <slamkit/factors/pose_graph_optimizer.h>
#include <slamkit/sim/pose_graph_generator.h>

#include <iostream>

int main() {
  slamkit::PoseGraphSimOptions o;
  o.world = "sphere";
  o.rings = 6;
  o.poses_per_ring = 10;
  slamkit::PoseGraph g = slamkit::generate_pose_graph(o);
  const slamkit::PoseGraphResult r = slamkit::optimize_pose_graph(g);
  std::cout << "consumer: chi2 " << r.input_chi2 << " -> " << r.final_chi2 << " with " << r.summary.linear_solver << "\n";
  return r.summary.success() && r.final_chi2 < r.input_chi2 ? 0 : 1;
}
