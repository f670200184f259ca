// optimize_pose_graph: the whole pose-graph pipeline in one call —
//   gauge → fill-reducing order (computed once, shared by every linear system) →
//   initialization (init) → FactorGraph → Optimizer → estimates written back.
// Defaults are the fastest combination measured on the standard datasets (bench/results):
// initialization `auto` (LAGO-style linear in 2D, chordal in 3D; if the objective after it is
// above its degrees of freedom, a second run from the spanning-tree guess, lower minimum kept)
// and Gauss-Newton with the best-iterate safeguard.
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
  /// With init = auto: when the objective after initialization exceeds this × its degrees of
  /// freedom (residuals − free tangent dimensions), the guess disagrees with the measurements
  /// by more than their noise and may be in a wrong basin; the graph is then optimized a second
  /// time from the spanning-tree guess and the lower minimum kept (0: never). Why 1.5 and not 1:
  /// a good start on data whose noise model is exact begins just above its degrees of freedom
  /// (generated Manhattan graphs of 100k and 1M poses: 1.01; the retry then doubled time and
  /// memory to gain 0.002 in chi2); the reference files that start in the right basin are at
  /// ≤ 0.83, M3500b's LAGO start at 3.04.
  double retry_chi2_per_dof = 1.5;
  /// With init = auto on a 2D graph: when the graph's own estimates already fit the measurements
  /// (χ² at them ≤ this × degrees of freedom, every vertex estimated, no calibration), they are
  /// the start and no initialization runs (InitSummary::used = none, with a note). Why 1: χ² at
  /// the optimum of a graph with an exact noise model is about its degrees of freedom, so a start
  /// below it is already at the noise level (intel.g2o: 0.23, the same minimum in the same 3
  /// Gauss-Newton iterations as after LAGO; the 2D reference files built from odometry start at
  /// 438 to 7·10⁷). 3D graphs always get the chordal initialization, which costs about a quarter
  /// of an iteration (parking-garage starts at 0.60 and needs one iteration more without it).
  /// 0: always initialize.
  double keep_estimates_chi2_per_dof = 1.0;
  OptimizerOptions optimizer;
  PoseGraphProblemOptions problem;
};

/// Wall time of each phase of optimize_pose_graph (seconds); the optimizer's own phases are in
/// Summary (setup, symbolic analysis, linearize, evaluate, linear solver), the
/// initialization's in InitSummary.
struct PoseGraphPhaseTimes {
  double input_chi2_s = 0.0;  ///< chi2 of the file's estimates
  double ordering_s = 0.0;    ///< fill-reducing order over the vertices
  double gauge_s = 0.0;       ///< gauge choice and connectivity check
  double init_s = 0.0;
  double chi2_after_init_s = 0.0;  ///< 0 when the optimizer's first linearization gives it
  double problem_s = 0.0;          ///< FactorGraph + Values from the PoseGraph
  double optimize_s = 0.0;
  double write_back_s = 0.0;  ///< estimates copied into the PoseGraph, final chi2
};

struct PoseGraphResult {
  InitSummary init;
  Summary summary;
  double input_chi2 = 0.0;       ///< g2o chi2 of the estimates the graph came with
  double chi2_after_init = 0.0;  ///< after initialization
  double final_chi2 = 0.0;       ///< g2o chi2 (no robust kernel) of the result
  double time_ordering_s = 0.0;
  double time_total_s = 0.0;     ///< ordering + initialization + problem build + optimization
  PoseGraphPhaseTimes phases;
  std::vector<std::string> notes;
  CalibrationReport calibration;  ///< estimates with marginal sigmas, when the graph has calibration variables
};

PoseGraphResult optimize_pose_graph(PoseGraph& g, const PoseGraphOptimizerOptions& options = {});

/// The result as the JSON document of `slamkit optimize --json` (a string, like
/// Summary::to_json, whose fields it extends): the graph's format, dimension and counts, init
/// used and requested, the chi2 before and after initialization and at the end (g2o metric),
/// the optimizer's costs, the phase times, notes, and the calibration estimates when there are
/// any. The CLI adds what only it knows (label, file, load time, the run's config); Python's
/// optimize_pose_graph(as_dict=True) returns it as a dict.
std::string pose_graph_result_to_json(const PoseGraphResult& result, const PoseGraph& graph);

}  // namespace slamkit
