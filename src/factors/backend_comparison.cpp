#include "slamkit/factors/backend_comparison.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/hogman.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/solvers/relaxer_init.h"

namespace slamkit {
namespace {

bool is_manifold_solver(const std::string& s) { return s == "gn" || s == "lm" || s == "tr-lm" || s == "dogleg"; }

BackendRun run_manifold(PoseGraph g, const std::string& solver, const ComparisonOptions& o) {
  PoseGraphOptimizerOptions po;
  po.init = InitMethod::kNone;
  po.optimizer.algorithm = parse_algorithm(solver);
  po.optimizer.max_iterations = o.max_iterations;
  po.optimizer.num_threads = o.threads;
  const auto t0 = std::chrono::steady_clock::now();
  po.optimizer.callback = [&](const IterationSummary&) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < o.time_budget_s;
  };
  const PoseGraphResult r = optimize_pose_graph(g, po);
  BackendRun run;
  run.solver = solver;
  run.initial_chi2 = r.input_chi2;
  run.final_chi2 = r.final_chi2;
  run.time_total_s = r.time_total_s;
  run.iterations = r.summary.iterations;
  run.termination = to_string(r.summary.termination);
  // The optimizer's clock starts after the ordering: shift its times by what came before.
  const double offset = r.time_total_s - r.summary.time_total_s;
  double best = r.input_chi2;
  run.trace.emplace_back(0.0, r.input_chi2);
  for (const IterationSummary& it : r.summary.trace) {
    if (it.iteration == 0) continue;
    if (it.accepted) best = std::min(best, it.cost);
    run.trace.emplace_back(offset + it.cumulative_time_s, best);  // the best iterate so far
  }
  return run;
}

BackendRun run_relaxer_backend(PoseGraph g, const std::string& solver, const ComparisonOptions& o) {
  RelaxerStop stop;
  stop.max_iterations = o.max_iterations;
  stop.time_budget_s = o.time_budget_s;
  stop.relative_tolerance = 1e-9;  // let the slow ones run until the budget
  HogmanOptions h;
  h.stop = stop;
  h.threads = o.threads;
  const RelaxerSummary s = solver == "hogman" ? optimize_hogman(g, h) : run_named_relaxer(g, solver, stop);
  BackendRun run;
  run.solver = solver;
  run.initial_chi2 = s.initial_chi2;
  run.final_chi2 = s.final_chi2;
  run.time_total_s = s.time_total_s;
  run.iterations = s.iterations;
  run.termination = s.termination;
  for (const RelaxerIteration& it : s.trace) run.trace.emplace_back(it.time_s, it.chi2);
  return run;
}

}  // namespace

PoseGraph comparison_start(const PoseGraph& g, const std::string& init, double* time_s) {
  const auto t0 = std::chrono::steady_clock::now();
  PoseGraph start = g;
  if (init == "zero") {
    for (std::size_t i = 0; i < start.vertices().size(); ++i) {
      GraphVertex& v = start.vertex_at(i);
      v.pose2 = SE2();
      v.pose3 = SE3();
      v.point.setZero();
    }
  } else if (init != "none") {
    const InitMethod m = parse_init_method(init);
    if (m != InitMethod::kOdometry && m != InitMethod::kSpanningTree && m != InitMethod::kAuto &&
        m != InitMethod::kLinear && m != InitMethod::kChordal)
      throw InputError("", 0, "init", "compare starts from odometry, spanning-tree, auto, linear, chordal, zero or none");
    initialize_pose_graph(start, m, gauge_vertices(start));
  }
  if (time_s) *time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return start;
}

Comparison compare_backends(const PoseGraph& g, const ComparisonOptions& o) {
  if (!(o.time_budget_s > 0)) throw InputError("", 0, "time-budget", "must be > 0 seconds");
  if (o.solvers.empty()) throw InputError("", 0, "solvers", "no back end named");
  for (const std::string& s : o.solvers)
    if (!is_manifold_solver(s) && s != "sgd" && s != "toro" && s != "relax" && s != "mlr" && s != "hogman")
      throw InputError("", 0, "solvers",
                       "unknown back end '" + s + "' (gn, lm, tr-lm, dogleg, sgd, toro, relax, mlr, hogman)");
  Comparison c;
  c.file = g.source;
  c.dimension = g.dimension();
  c.vertices = static_cast<int>(g.vertices().size());
  c.edges = static_cast<int>(g.edges.size());
  c.init = o.init;
  const PoseGraph start = comparison_start(g, o.init, &c.time_init_s);
  c.start_chi2 = total_chi2(start);
  for (const std::string& s : o.solvers) {
    BackendRun run;
    try {
      run = is_manifold_solver(s) ? run_manifold(start, s, o) : run_relaxer_backend(start, s, o);
    } catch (const InputError& e) {  // e.g. a relaxer on a graph with landmarks: report, go on
      run.solver = s;
      run.initial_chi2 = run.final_chi2 = c.start_chi2;
      run.error = e.what();
      run.termination = "refused";
      run.trace.emplace_back(0.0, c.start_chi2);
    }
    if (o.progress)
      std::printf("  %-7s chi2 %.10g -> %.10g in %d iterations, %.3f s (%s)\n", s.c_str(), run.initial_chi2,
                  run.final_chi2, run.iterations, run.time_total_s,
                  run.error.empty() ? run.termination.c_str() : run.error.c_str());
    std::fflush(stdout);
    c.runs.push_back(std::move(run));
  }
  c.best_chi2 = c.runs.front().final_chi2;
  for (const BackendRun& r : c.runs)
    if (r.error.empty()) c.best_chi2 = std::min(c.best_chi2, r.final_chi2);
  for (BackendRun& r : c.runs)
    for (const auto& [t, chi2] : r.trace)
      if (chi2 <= c.best_chi2 * (1 + o.reach_tolerance)) {
        r.time_to_reach_s = t;
        break;
      }
  std::stable_sort(c.runs.begin(), c.runs.end(), [](const BackendRun& a, const BackendRun& b) {
    if (a.error.empty() != b.error.empty()) return a.error.empty();
    const bool ra = a.time_to_reach_s >= 0, rb = b.time_to_reach_s >= 0;
    if (ra != rb) return ra;
    if (ra) return a.time_to_reach_s < b.time_to_reach_s;
    return a.final_chi2 < b.final_chi2;
  });
  return c;
}

}  // namespace slamkit
