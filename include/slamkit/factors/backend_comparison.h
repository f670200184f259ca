// Every pose-graph back end side by side (`slamkit compare`): the manifold solvers (gn, lm,
// tr-lm, dogleg), the relaxers (sgd, toro, relax, mlr) and HOG-Man each run from the same start on a
// copy of the graph, with chi2 (g2o definition) recorded against wall time and iterations.
// The ranking orders the runs by final chi2, then by the time they first came within
// `reach_tolerance` of the best chi2 any of them found.
#pragma once

#include <string>
#include <vector>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

struct BackendRun {
  std::string solver;
  double initial_chi2 = 0, final_chi2 = 0, time_total_s = 0;
  int iterations = 0;
  std::string termination;
  std::vector<std::pair<double, double>> trace;  ///< (time_s, chi2), entry 0 the start
  double time_to_reach_s = -1;  ///< first time chi2 ≤ best · (1 + reach_tolerance); −1: never
  std::string error;            ///< non-empty: the back end refused the graph (message)
};

struct ComparisonOptions {
  std::vector<std::string> solvers{"gn", "lm", "tr-lm", "dogleg", "sgd", "toro", "relax", "mlr", "hogman"};
  /// Start for every back end: odometry | spanning-tree | auto | zero | none (the file's estimates).
  std::string init = "odometry";
  double time_budget_s = 10.0;   ///< per back end (> 0)
  int max_iterations = 1000;     ///< per back end
  int threads = 1;               ///< linearization threads of the manifold solvers
  double reach_tolerance = 1e-3;
  bool progress = true;          ///< one line per back end on stdout
};

struct Comparison {
  std::string file;
  int dimension = 0, vertices = 0, edges = 0;
  std::string init;
  double start_chi2 = 0, best_chi2 = 0, time_init_s = 0;
  std::vector<BackendRun> runs;  ///< ranked, best first
};

/// The start every back end shares: `init` applied to a copy of g ("zero": all poses at the
/// identity). Throws InputError for an unknown name.
PoseGraph comparison_start(const PoseGraph& g, const std::string& init, double* time_s = nullptr);

Comparison compare_backends(const PoseGraph& g, const ComparisonOptions& options);

}  // namespace slamkit
