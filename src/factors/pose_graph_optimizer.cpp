#include "slamkit/factors/pose_graph_optimizer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit {
namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// Degrees of freedom of the graph's least-squares problem at the file's estimates: residual
/// rows (Σ edge dimensions) minus the free tangent dimensions (vertices not in the gauge).
double degrees_of_freedom(const PoseGraph& g, const std::vector<std::int64_t>& gauge) {
  double rows = 0.0, free = 0.0;
  for (const GraphEdge& e : g.edges) rows += static_cast<double>(e.information.rows());
  for (const GraphVertex& v : g.vertices()) free += tangent_dim(v.kind);
  for (std::int64_t id : gauge) free -= tangent_dim(g.vertex(id).kind);
  return rows - free;
}

/// init = auto on a 2D graph starts from the file's estimates when they already fit the
/// measurements within their noise (χ² ≤ keep_estimates_chi2_per_dof × degrees of freedom, every
/// vertex estimated, no calibration): an initialization exists to leave a start in a wrong basin,
/// and a start whose objective is at the noise level is not one (the counterpart of
/// retry_chi2_per_dof). In 3D the chordal initialization (two systems of 3×3 blocks) costs about a
/// quarter of a Gauss-Newton iteration (6×6 blocks), so it pays as soon as it saves an iteration:
/// it always runs.
InitMethod resolve_auto_init(const PoseGraph& g, const PoseGraphOptimizerOptions& options,
                             const std::vector<std::int64_t>& gauge, double input_chi2, std::vector<std::string>* notes) {
  if (options.init != InitMethod::kAuto || !(options.keep_estimates_chi2_per_dof > 0.0) || g.dimension() != 2)
    return options.init;
  for (const GraphVertex& v : g.vertices())
    if (!v.has_estimate) return options.init;
  for (const GraphEdge& e : g.edges)
    if (e.calibrated) return options.init;
  const double dof = degrees_of_freedom(g, gauge);
  if (!(dof > 0.0) || !(input_chi2 <= options.keep_estimates_chi2_per_dof * dof)) return options.init;
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "the graph's estimates fit its measurements (chi2 %.6g <= %.3g x %.0f degrees of freedom): optimized "
                "from them without an initialization (--init linear|chordal to run one)",
                input_chi2, options.keep_estimates_chi2_per_dof, dof);
  notes->push_back(buf);
  return InitMethod::kNone;
}
}  // namespace

PoseGraphResult optimize_pose_graph(PoseGraph& g, const PoseGraphOptimizerOptions& options) {
  if (g.vertices().empty())
    throw InputError(g.source, 0, "", g.edges.empty() ? "the graph holds no vertices and no edges: nothing to optimize"
                                                      : "the graph holds edges but no vertices");
  const auto t_start = std::chrono::steady_clock::now();
  PoseGraphResult r;
  PoseGraphPhaseTimes& ph = r.phases;
  auto t_phase = t_start;
  auto lap = [&t_phase](double& into) {
    const auto now = std::chrono::steady_clock::now();
    into = std::chrono::duration<double>(now - t_phase).count();
    t_phase = now;
  };
  r.input_chi2 = total_chi2(g);
  lap(ph.input_chi2_s);

  // One elimination order over all vertices (graph order = Values order), reused by the
  // initialization systems and the optimizer.
  const auto t_order = std::chrono::steady_clock::now();
  std::vector<std::pair<int, int>> adjacency;
  adjacency.reserve(g.edges.size());
  for (const GraphEdge& e : g.edges)
    adjacency.emplace_back(static_cast<int>(*g.index_of(e.from)), static_cast<int>(*g.index_of(e.to)));
  const EliminationOrder order =
      compute_elimination_order(static_cast<int>(g.vertices().size()), adjacency, options.optimizer.ordering);
  r.time_ordering_s = seconds_since(t_order);
  lap(ph.ordering_s);

  std::vector<std::string> gauge_notes;
  const std::vector<std::int64_t> gauge = gauge_vertices(g, &gauge_notes);
  lap(ph.gauge_s);
  InitOptions init_options;
  init_options.linear_solver = options.optimizer.linear_solver;
  init_options.ordering = options.optimizer.ordering;
  init_options.threads = options.optimizer.blas_threads > 0 ? options.optimizer.blas_threads : options.optimizer.num_threads;
  init_options.vertex_order = order;
  const InitMethod init = resolve_auto_init(g, options, gauge, r.input_chi2, &r.notes);
  r.init = initialize_pose_graph(g, init, gauge, init_options);
  r.init.requested = options.init;
  if (init != options.init) r.init.notes = r.notes;
  lap(ph.init_s);
  PoseGraphProblem problem = build_pose_graph_problem(g, options.problem, &gauge, &gauge_notes);
  lap(ph.problem_s);
  // Without a kernel or calibration the optimizer's initial cost is this chi2: no extra pass.
  const bool cost_is_chi2 = !options.problem.kernel && problem.calibration.empty();
  if (init == InitMethod::kNone) r.chi2_after_init = r.input_chi2;
  else if (!cost_is_chi2) r.chi2_after_init = total_chi2(g);
  lap(ph.chi2_after_init_s);

  r.notes.insert(r.notes.end(), problem.notes.begin(), problem.notes.end());
  OptimizerOptions opt = options.optimizer;
  opt.variable_order = order;
  opt.shared_symbolic = std::move(r.init.symbolic);  // the initialization's pattern analysis, if H's pattern is its
  // Calibration variables (after the vertices in Values) are eliminated last. After the run,
  // parameters the data does not determine are restored to their initial values and held
  // there by tight priors, and the problem is optimized again (factors/calibration_problem.h).
  for (std::size_t i = g.vertices().size(); i < problem.values.size(); ++i)
    opt.variable_order.order.push_back(static_cast<int>(i));
  const Values initial = problem.calibration.empty() ? Values() : problem.values;
  {
    double more = 0.0;
    lap(more);
    ph.problem_s += more;
  }
  r.summary = Optimizer(opt).optimize(problem.graph, problem.values);
  if (init != InitMethod::kNone && cost_is_chi2) r.chi2_after_init = r.summary.initial_cost;
  // A guess that disagrees with the measurements by more than their noise (objective above its
  // degrees of freedom) may sit in a wrong basin: also optimize from the spanning-tree guess and
  // keep the lower minimum. The test costs nothing; the second run happens only when it fires.
  const double dof = static_cast<double>(r.summary.num_residuals - r.summary.tangent_dim);
  if (options.init == InitMethod::kAuto && options.retry_chi2_per_dof > 0.0 && problem.calibration.empty() &&
      dof > 0.0 && r.summary.initial_cost > options.retry_chi2_per_dof * dof) {
    PoseGraph alternative = g;  // the gauge vertices still hold the file's values
    const InitSummary tree = initialize_pose_graph(alternative, InitMethod::kSpanningTree, gauge, init_options);
    PoseGraphProblem second = build_pose_graph_problem(alternative, options.problem, &gauge, &gauge_notes);
    Summary s2 = Optimizer(opt).optimize(second.graph, second.values);
    r.init.time_s += tree.time_s;
    char buf[320];
    const bool better = s2.success() && s2.final_cost < r.summary.final_cost;
    std::snprintf(buf, sizeof(buf),
                  "objective after the %s initialization %.6g > its %.0f degrees of freedom: also optimized from the "
                  "spanning-tree guess, which ends at %.10g (%s initialization: %.10g); kept the %s",
                  to_string(r.init.used), r.summary.initial_cost, dof, s2.final_cost, to_string(r.init.used),
                  r.summary.final_cost, better ? "spanning-tree result" : "first result");
    r.notes.push_back(buf);
    r.init.notes.push_back(buf);
    if (better) {
      problem = std::move(second);
      r.summary = std::move(s2);
      r.init.used = InitMethod::kSpanningTree;
      if (cost_is_chi2) r.chi2_after_init = r.summary.initial_cost;
      else r.chi2_after_init = total_chi2(alternative);
    }
  }
  if (!problem.calibration.empty()) {
    const CalibrationOptions& co = options.problem.calibration;
    r.calibration = analyze_calibration(problem.graph, problem.values, problem.calibration, co);
    std::vector<std::string> held, warnings;
    for (;;) {
      const CalibrationParameterEstimate* worst = nullptr;
      for (const CalibrationParameterEstimate& p : r.calibration.parameters)
        if (!p.observable && std::find(held.begin(), held.end(), p.name) == held.end() &&
            (!worst || p.excitation < worst->excitation))
          worst = &p;
      if (!worst || !hold_calibration_parameter(worst->name, problem.calibration, initial, problem.graph)) break;
      held.push_back(worst->name);
      warnings.push_back("calibration parameter " + worst->name + " is unobservable (" + worst->reason +
                         "); held at its initial value");
      problem.values = initial;
      r.summary = Optimizer(opt).optimize(problem.graph, problem.values);
      r.calibration = analyze_calibration(problem.graph, problem.values, problem.calibration, co);
    }
    if (!held.empty())
      r.notes.push_back("optimized again with " + std::to_string(held.size()) +
                        " unobservable calibration parameters held at their initial values");
    r.calibration.held = held;
    r.calibration.warnings = warnings;
    for (CalibrationParameterEstimate& p : r.calibration.parameters) {
      if (std::find(held.begin(), held.end(), p.name) == held.end()) continue;
      p.observable = false;
      p.sigma = std::numeric_limits<double>::quiet_NaN();
    }
  }
  lap(ph.optimize_s);
  copy_estimates(problem.values, g);
  r.final_chi2 = options.problem.kernel || !problem.calibration.empty() ? total_chi2(g) : r.summary.final_cost;
  lap(ph.write_back_s);
  r.time_total_s = seconds_since(t_start);
  return r;
}

}  // namespace slamkit
