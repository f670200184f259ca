// Initial guesses for pose graphs, computed from the measurements alone.
//
//   odometry       compose the odometry chain i → i+1 from the gauge, then breadth-first
//   spanning-tree  compose along a breadth-first spanning tree from the gauge vertices
//   linear  (2D)   LAGO-style: (1) orientations by linear least squares on θ_j − θ_i = δθ_ij + 2πk_ij,
//                  with the wraps k_ij fixed by the spanning-tree orientations and weights
//                  1/σ²_θ (marginal of the edge covariance); (2) positions by linear least squares
//                  on p_j − p_i = R_i R_z... t_ij given those orientations (g2o's error metric)
//   chordal (3D)   chordal relaxation of rotations, min Σ w ‖R_j − R_i Z_ij‖²_F (one 3N×3N
//                  system, three right-hand sides), projected to SO(3); then positions as above
//   auto           linear in 2D, chordal in 3D
//   sgd|toro|relax|mlr  the classic relaxers (solvers/relaxer_init.h) run from the file's estimates
// Landmarks get their estimate from the first pose that observes them. The gauge vertices keep
// their values. The linear systems share the optimizer's sparse Cholesky.
#pragma once

#include <string>
#include <vector>

#include "slamkit/core/pose_graph.h"
#include "slamkit/linear/sparse_cholesky.h"

namespace slamkit {

enum class InitMethod { kNone, kOdometry, kSpanningTree, kLinear, kChordal, kAuto, kSgd, kToro, kRelax, kMlr };
const char* to_string(InitMethod m);  ///< "none", "odometry", "spanning-tree", "linear", "chordal", "auto", "sgd", "toro", "relax", "mlr"
InitMethod parse_init_method(const std::string& s);

struct InitSummary {
  InitMethod requested = InitMethod::kNone;
  InitMethod used = InitMethod::kNone;  ///< auto resolved to linear/chordal
  double time_s = 0.0;
  // Phases of time_s (linear/chordal): spanning tree (orientation wraps), symbolic analyses
  // of the linear systems, their assembly, numeric factorization + solve, landmark guesses.
  double time_tree_s = 0.0, time_analyze_s = 0.0, time_assemble_s = 0.0, time_solve_s = 0.0, time_points_s = 0.0;
  int analyses = 0;  ///< symbolic analyses of block patterns the initialization ran (shared ones not counted)
  /// The pattern analysis of its linear systems (null if not shareable): the optimizer of a
  /// pose-only graph, whose H has the same block pattern, adopts it instead of analyzing again.
  SharedSymbolic symbolic;
  std::vector<std::string> notes;
};

struct InitOptions {
  SparseBackend linear_solver = SparseBackend::kAuto;
  OrderingMethod ordering = OrderingMethod::kAuto;
  int threads = 1;  ///< BLAS threads of the factorizations
  /// Elimination order over graph vertex indices, shared with the optimizer (empty: each
  /// linear system computes its own).
  EliminationOrder vertex_order;
};

/// Overwrites the estimates of all non-gauge vertices. Throws InputError if the method does
/// not fit the graph (e.g. chordal on a 2D graph).
InitSummary initialize_pose_graph(PoseGraph& g, InitMethod method, const std::vector<std::int64_t>& gauge,
                                  const InitOptions& options = {});

}  // namespace slamkit
