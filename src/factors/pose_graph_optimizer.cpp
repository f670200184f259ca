#include "slamkit/factors/pose_graph_optimizer.h"

#include <chrono>

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
  r.summary = Optimizer(opt).optimize(problem.graph, problem.values);
  copy_estimates(problem.values, g);
  r.final_chi2 = options.problem.kernel ? total_chi2(g) : r.summary.final_cost;
  r.time_total_s = seconds_since(t_start);
  return r;
}

}  // namespace slamkit
