// optimize_pose_graph: the whole pose-graph pipeline in one call —
//   gauge → fill-reducing order (computed once, shared by every linear system) →
//   initialization (init) → FactorGraph → Optimizer → estimates written back.
// Defaults are the fastest combination measured on the standard datasets (bench/results):
// initialization `auto` (LAGO-style linear in 2D, chordal in 3D) and Gauss-Newton with the
// best-iterate safeguard.
#pragma once

#include <string>
#include <vector>

#include "slamkit/factors/pose_graph_problem.h"
#include "slamkit/solvers/optimizer.h"
#include "slamkit/solvers/pose_graph_init.h"

namespace slamkit {

struct PoseGraphOptimizerOptions {
  PoseGraphOptimizerOptions() { optimizer.algorithm = Algorithm::kGaussNewton; }
  InitMethod init = InitMethod::kAuto;
  OptimizerOptions optimizer;
  PoseGraphProblemOptions problem;
};

struct PoseGraphResult {
  InitSummary init;
  Summary summary;
  double input_chi2 = 0.0;       ///< g2o chi2 of the estimates the graph came with
  double chi2_after_init = 0.0;  ///< after initialization
  double final_chi2 = 0.0;       ///< g2o chi2 (no robust kernel) of the result
  double time_ordering_s = 0.0;
  double time_total_s = 0.0;     ///< ordering + initialization + problem build + optimization
  std::vector<std::string> notes;
  CalibrationReport calibration;  ///< estimates with marginal sigmas, when the graph has calibration variables
};

PoseGraphResult optimize_pose_graph(PoseGraph& g, const PoseGraphOptimizerOptions& options = {});

}  // namespace slamkit
