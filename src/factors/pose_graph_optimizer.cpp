#include "slamkit/factors/pose_graph_optimizer.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit {
namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

PoseGraphResult optimize_pose_graph(PoseGraph& g, const PoseGraphOptimizerOptions& options) {
  if (g.vertices().empty())
    throw InputError(g.source, 0, "", g.edges.empty() ? "the graph holds no vertices and no edges: nothing to optimize"
                                                      : "the graph holds edges but no vertices");
  const auto t_start = std::chrono::steady_clock::now();
  PoseGraphResult r;
  r.input_chi2 = total_chi2(g);

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

  const std::vector<std::int64_t> gauge = gauge_vertices(g);
  InitOptions init_options;
  init_options.linear_solver = options.optimizer.linear_solver;
  init_options.ordering = options.optimizer.ordering;
  init_options.threads = options.optimizer.blas_threads > 0 ? options.optimizer.blas_threads : options.optimizer.num_threads;
  init_options.vertex_order = order;
  r.init = initialize_pose_graph(g, options.init, gauge, init_options);
  r.chi2_after_init = options.init == InitMethod::kNone ? r.input_chi2 : total_chi2(g);

  PoseGraphProblem problem = build_pose_graph_problem(g, options.problem);
  r.notes = problem.notes;
  OptimizerOptions opt = options.optimizer;
  opt.variable_order = order;
  // Calibration variables (after the vertices in Values) are eliminated last. After the run,
  // parameters the data does not determine are restored to their initial values and held
  // there by tight priors, and the problem is optimized again (factors/calibration_problem.h).
  for (std::size_t i = g.vertices().size(); i < problem.values.size(); ++i)
    opt.variable_order.order.push_back(static_cast<int>(i));
  const Values initial = problem.calibration.empty() ? Values() : problem.values;
  r.summary = Optimizer(opt).optimize(problem.graph, problem.values);
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
  copy_estimates(problem.values, g);
  r.final_chi2 = options.problem.kernel || !problem.calibration.empty() ? total_chi2(g) : r.summary.final_cost;
  r.time_total_s = seconds_since(t_start);
  return r;
}

}  // namespace slamkit
