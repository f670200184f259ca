// HOG-Man: hierarchical optimization on manifolds (Grisetti, Kümmerle, Stachniss, Frese,
// Hertzberg, ICRA 2010).
//
// Hierarchy: level 0 is the pose graph; level l+1 groups the nodes of level l in runs of
// `group_size` consecutive ids, each group represented by its first node. Two groups joined by
// an edge get one condensed edge between their representatives: the subgraph of the two
// groups is optimized on the manifold with the first representative fixed (dense
// Gauss-Newton), the measurement is the relative pose of the two representatives in that local
// solution and the information is the marginal of the second (the Schur complement of the
// local Hessian), mapped into the g2o error coordinates of the condensed edge.
// Optimization is top-down: the coarsest graph (a few dozen nodes) is initialized
// (`top_init`) and solved with Gauss-Newton; each level below moves every group rigidly with
// its representative and re-optimizes, holding the neighbours fixed, only the groups whose
// representative moved more than `refine_threshold` — the fine level is refined only where
// the coarse solution changed. The batch method starts the fine level from `fine_init`,
// iterates the intermediate levels on the way down and ends with a damped (LM) fine pass.
//
// Online (hogman_online): the graph grows one pose at a time in id order with its edges to
// the poses already there; only the groups that received a node or an edge are condensed again,
// the top level is re-solved when an edge closes a loop between groups that are not neighbours
// in the sequence, and changes travel down only where representatives moved. When the replay
// ends, a final fine-level pass (all levels brought up to date, a few Gauss-Newton iterations on
// the fine level) gives the full solution; its time is reported apart from the additions.
#pragma once

#include <vector>

#include "slamkit/core/pose_graph.h"
#include "slamkit/solvers/optimizer_options.h"
#include "slamkit/solvers/pose_graph_init.h"
#include "slamkit/solvers/relaxer.h"

namespace slamkit {

struct HogmanOptions {
  RelaxerStop stop;
  int group_size = 8;             ///< nodes per group at every level (≥ 2)
  int max_levels = 3;             ///< coarse levels above the pose graph
  int top_nodes = 64;             ///< stop adding levels once a level has at most this many nodes
  int local_iterations = 3;       ///< Gauss-Newton iterations of a condensation or a group refinement
  int refine_sweeps = 1;          ///< Gauss-Seidel sweeps over the moved groups at each level
  double refine_threshold = 1e-4; ///< max |Log(x_old⁻¹ x_new)| of a representative that triggers refinement
  /// Batch: the initial guess of the fine level before the hierarchy is built (the manifold
  /// solvers' default: LAGO in 2D, chordal in 3D). The condensed edges come from local solves
  /// started at the fine estimates, so a globally consistent start makes them consistent too;
  /// kNone keeps the graph's estimates.
  InitMethod fine_init = InitMethod::kAuto;
  InitMethod top_init = InitMethod::kAuto;  ///< initialization of the coarsest graph (batch)
  int top_iterations = 20;        ///< Gauss-Newton iterations on the coarsest graph
  int level_iterations = 2;       ///< Gauss-Newton iterations on an intermediate level (online)
  bool online_level_iterations = false;  ///< online: after a loop closure, also iterate the intermediate levels
  /// Batch: each intermediate level, once moved into place by the level above, also gets
  /// `level_iterations` Gauss-Newton iterations as a whole, so the level below starts from a
  /// solution of its own condensed graph rather than from rigid group moves only.
  bool batch_level_iterations = true;
  /// The fine-level pass that ends batch HOG-Man: damped (LM), because the hierarchy pass can
  /// leave the fine poses far enough from the optimum that undamped Gauss-Newton diverges
  /// into a worse minimum (M3500b, cubicle).
  Algorithm fine_algorithm = Algorithm::kLevenbergMarquardt;
  /// LM slows down near the optimum where Gauss-Newton converges quadratically: the fine pass
  /// is the final answer, so it runs to a tight relative cost change (INTEL: 215.854 at 1e-5).
  double fine_function_tolerance = 1e-8;
  /// Online: when the replay ends (the user asks for the full solution), bring every level up
  /// to date top-down and run `final_fine_iterations` Gauss-Newton iterations on the fine
  /// level from the online estimates; its time is reported apart from the additions.
  bool final_fine_pass = true;
  int final_fine_iterations = 3;
  int threads = 1;
};

/// Batch HOG-Man on g (pose–pose edges only). Trace: iteration 1 the fine start and the
/// hierarchy pass (chi2 of the fine poses it leaves), iteration 2 the fine LM pass.
RelaxerSummary optimize_hogman(PoseGraph& g, const HogmanOptions& options = {});

struct HogmanOnlineResult {
  std::vector<int> graph_size;        ///< poses in the graph after each addition
  std::vector<double> time_per_pose_s;      ///< wall time of each addition
  std::vector<double> cpu_time_per_pose_s;  ///< CPU time of each addition (this process; threads = 1)
  std::vector<char> top_solved;       ///< the coarsest level was re-solved on this addition
  double final_chi2 = 0, total_time_s = 0;  ///< total_time_s: the additions, without the final pass
  double chi2_before_final_pass = 0;        ///< the online estimates as the last addition left them
  double final_pass_time_s = 0;             ///< 0 without final_fine_pass
  double final_pass_cpu_time_s = 0;
  int levels = 0;
};

/// Replays g one pose at a time (id order) and leaves the online estimates in g.
HogmanOnlineResult hogman_online(PoseGraph& g, const HogmanOptions& options = {});

}  // namespace slamkit
