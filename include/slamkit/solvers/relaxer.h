// What the classic pose-graph relaxers (SGD, TORO, Gauss-Seidel relaxation, multi-level
// relaxation, HOG-Man) share: the stopping rules, the per-iteration record and the summary.
//
// Every relaxer works on a PoseGraph in place (pose–pose edges only; landmarks are refused),
// holds the gauge vertices (FIX, else the smallest id) fixed, and measures its progress in
// g2o's chi2 = Σ eᵀ Ω e (core/pose_graph_error.h), so its numbers compare directly with the
// manifold solvers. An iteration is one pass over all constraints (SGD, TORO, relaxation),
// one linearization + V-cycles (MLR) or one hierarchy update (HOG-Man).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

struct RelaxerIteration {
  int iteration = 0;      ///< 0: the initial state
  double chi2 = 0.0;      ///< g2o chi2 after this iteration
  double chi2_change = 0.0;  ///< previous chi2 − this one
  double time_s = 0.0;    ///< wall time since the start of the run (chi2 evaluation included)
  double step = 0.0;      ///< max |change| of a pose parameter in this iteration
};

/// Stopping rules shared by all relaxers.
struct RelaxerStop {
  int max_iterations = 100;
  double time_budget_s = 0.0;         ///< > 0: stop after the first iteration that ends past it
  double relative_tolerance = 1e-6;   ///< stop when |Δchi2| ≤ tol · chi2 over `patience` iterations
  int patience = 3;
  /// Called after every iteration (entry 0 too); return false to stop.
  std::function<bool(const RelaxerIteration&)> callback;
};

/// The second phase of SGD and TORO in 2D (the first is the papers' update, whose per-constraint
/// path-length factor c_e = l / Σ_path 1/M_k makes it fast but moves its fixed point to the
/// minimum of Σ c_e χ²_e). From iteration `start` on, each update is the preconditioned
/// gradient of the true chi2 (Olson's Δp_k = λ M_k⁻¹ Jᵀ W r): one learning rate for every
/// constraint, λ = C / (γ (t0 + t − start)) with C the `quantile` of the c_e, and the full
/// Jacobian, i.e. also ∂r_xy/∂θ_a (the measured translation turns with pose a), a step on the θ
/// increments from the root to a. Its fixed point is the least-squares optimum. It begins when
/// the papers' update stalls: the best chi2 fell by less than `stall` (relative) over `window`
/// iterations.
struct RelaxerGradientPhase {
  int start = 0;            ///< > 0: the phase's first iteration is start + 1; 0: when stalled; < 0: never
  double stall = 0.02;
  int window = 20;
  double t0 = 10;           ///< the phase's learning rate starts at C / (γ t0)
  double quantile = 0.5;    ///< C: this quantile of the constraints' path-length factors
  double max_turn = 0.01;   ///< [rad] bound of one constraint's coupling step on θ_a
};

struct RelaxerSummary {
  std::string method;       ///< "sgd", "toro", "relax", "mlr", "hogman"
  int dimension = 2;
  int num_poses = 0, num_edges = 0, num_loop_closures = 0;
  double initial_chi2 = 0.0, final_chi2 = 0.0;
  int iterations = 0;
  double time_total_s = 0.0;
  std::string termination;  ///< "max iterations", "time budget", "converged", "user callback", "no loop closure"
  std::vector<std::string> notes;
  std::vector<RelaxerIteration> trace;  ///< entry 0: the initial state

  std::string report() const;
  static std::string progress_header();
  static std::string progress_line(const RelaxerIteration& it);
  /// {"kind": "optimize", "solver": method, "initial_chi2", "final_chi2", "iterations",
  ///  "time_total_s", "termination", "trace": [{"iteration", "cost", "time_s"}]} — the keys
  /// `slamkit report` reads for optimizer runs.
  std::string to_json() const;
};

/// The pose graph as the relaxers see it: poses 0..n−1 in vertex order, gauge flags, and
/// per edge its two pose indices. Throws InputError (file, line, field) for landmarks, a graph
/// without poses, mixed dimensions, an edge whose information is not positive definite or not
/// finite, an estimate that is not finite, and a disconnected graph.
struct RelaxerGraph {
  int dimension = 2;
  std::vector<std::size_t> vertex;             ///< pose k → graph vertex index
  std::vector<char> gauge;                     ///< pose k held fixed?
  std::vector<std::pair<int, int>> ends;       ///< per edge (from, to) pose indices
  int num_loop_closures = 0;                   ///< edges beyond a spanning tree
};
RelaxerGraph make_relaxer_graph(const PoseGraph& g);

/// Runs the bookkeeping every relaxer shares: records iteration 0, calls `step(iteration)`
/// (which returns the max parameter change, or a negative number when the method is done) until a stopping rule fires, records chi2 and time
/// after each, and fills the summary. A non-finite chi2 stops the run with an error message
/// (never returned as a result): the estimates of the last finite iterate are restored.
RelaxerSummary run_relaxer(PoseGraph& g, const std::string& method, const RelaxerStop& stop,
                           const std::function<double(int)>& step, const std::function<void()>& write_back);

}  // namespace slamkit
