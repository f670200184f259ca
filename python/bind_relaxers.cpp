// Bindings of the classic pose-graph relaxers (SGD, TORO, Gauss-Seidel relaxation,
// multi-level relaxation, HOG-Man batch and online) and of `slamkit compare`, every back end
// from the same start. Each relaxer works on the PoseGraph in place and reports g2o's chi2.
#include <pybind11/functional.h>

#include "bind_callbacks.h"
#include "slamkit/core/pose_graph.h"
#include "slamkit/factors/backend_comparison.h"
#include "slamkit/factors/hogman.h"
#include "slamkit/solvers/gauss_seidel_relaxation.h"
#include "slamkit/solvers/multilevel_relaxation.h"
#include "slamkit/solvers/pose_graph_init.h"
#include "slamkit/solvers/relaxer.h"
#include "slamkit/solvers/sgd.h"
#include "slamkit/solvers/toro.h"

namespace slamkit::python {
namespace {

// The stopping rules every relaxer shares, with the Python callback (IterationRecord → bool|None)
// and the CLI's progress lines when verbose.
RelaxerStop make_stop(int max_iterations, double time_budget_s, double relative_tolerance, int patience,
                      const py::object& callback, bool verbose) {
  if (max_iterations < 0) throw py::value_error("max_iterations must be >= 0");
  require_finite(time_budget_s, "time_budget_s");
  require_finite(relative_tolerance, "relative_tolerance");
  if (time_budget_s < 0 || relative_tolerance < 0) throw py::value_error("time_budget_s and relative_tolerance must be >= 0");
  if (patience < 1) throw py::value_error("patience must be >= 1");
  if (!callback.is_none() && !PyCallable_Check(callback.ptr())) throw py::type_error("callback must be callable");
  RelaxerStop s;
  s.max_iterations = max_iterations;
  s.time_budget_s = time_budget_s;
  s.relative_tolerance = relative_tolerance;
  s.patience = patience;
  if (callback.is_none() && !verbose) return s;
  auto cb = share_python_object(callback);
  s.callback = [cb, verbose](const RelaxerIteration& it) {
    py::gil_scoped_acquire gil;
    if (verbose) {
      py::object out = py::module_::import("sys").attr("stdout");
      if (it.iteration == 0) out.attr("write")(RelaxerSummary::progress_header() + "\n");
      out.attr("write")(RelaxerSummary::progress_line(it) + "\n");
      out.attr("flush")();
    }
    if (cb->is_none()) return true;
    const py::object r = (*cb)(it);
    return r.is_none() || r.cast<bool>();
  };
  return s;
}

template <class Options, class Run>
RelaxerSummary run(PoseGraph& g, Options o, Run fn) {
  py::gil_scoped_release release;
  RelaxerSummary s = fn(g, o);
  return s;
}

#define SLAMKIT_STOP_ARGS                                                                           \
  py::arg("max_iterations") = 100, py::arg("time_budget_s") = 0.0, py::arg("relative_tolerance") = 1e-6, \
      py::arg("patience") = 3, py::arg("callback") = py::none(), py::arg("verbose") = false

py::dict comparison_dict(const Comparison& c) {
  py::dict d;
  d["file"] = c.file, d["dimension"] = c.dimension, d["vertices"] = c.vertices, d["edges"] = c.edges;
  d["init"] = c.init, d["start_chi2"] = c.start_chi2, d["best_chi2"] = c.best_chi2, d["time_init_s"] = c.time_init_s;
  py::list runs;
  for (const BackendRun& r : c.runs) {
    py::dict x;
    x["solver"] = r.solver, x["initial_chi2"] = r.initial_chi2, x["final_chi2"] = r.final_chi2;
    x["time_total_s"] = r.time_total_s, x["iterations"] = r.iterations, x["termination"] = r.termination;
    x["time_to_reach_s"] = r.time_to_reach_s, x["error"] = r.error;
    py::list trace;
    for (const auto& [t, chi2] : r.trace) trace.append(py::make_tuple(t, chi2));
    x["trace"] = trace;
    runs.append(x);
  }
  d["runs"] = runs;
  return d;
}

}  // namespace

void init_relaxers(py::module_& m) {
  py::class_<RelaxerIteration>(m, "RelaxerIteration", "One iteration of a relaxer (entry 0: the initial state).")
      .def_readonly("iteration", &RelaxerIteration::iteration)
      .def_readonly("chi2", &RelaxerIteration::chi2)
      .def_readonly("chi2_change", &RelaxerIteration::chi2_change)
      .def_readonly("time_s", &RelaxerIteration::time_s)
      .def_readonly("step", &RelaxerIteration::step);
  py::class_<RelaxerSummary>(m, "RelaxerSummary", "What a relaxer did (g2o chi2, iterations, why it stopped).")
      .def_readonly("method", &RelaxerSummary::method)
      .def_readonly("dimension", &RelaxerSummary::dimension)
      .def_readonly("num_poses", &RelaxerSummary::num_poses)
      .def_readonly("num_edges", &RelaxerSummary::num_edges)
      .def_readonly("num_loop_closures", &RelaxerSummary::num_loop_closures)
      .def_readonly("initial_chi2", &RelaxerSummary::initial_chi2)
      .def_readonly("final_chi2", &RelaxerSummary::final_chi2)
      .def_readonly("iterations", &RelaxerSummary::iterations)
      .def_readonly("time_total_s", &RelaxerSummary::time_total_s)
      .def_readonly("termination", &RelaxerSummary::termination)
      .def_readonly("notes", &RelaxerSummary::notes)
      .def_readonly("trace", &RelaxerSummary::trace)
      .def("report", &RelaxerSummary::report, "The summary `slamkit optimize --init` prints.")
      .def("to_dict", [](const RelaxerSummary& s) -> py::dict { return py::module_::import("json").attr("loads")(s.to_json()); },
           "The --json document `slamkit optimize --init` / `report` read.")
      .def("__repr__", [](const RelaxerSummary& s) {
        return "RelaxerSummary(method=" + s.method + ", final_chi2=" + std::to_string(s.final_chi2) +
               ", iterations=" + std::to_string(s.iterations) + ", termination=" + s.termination + ")";
      });

  m.def(
      "optimize_sgd",
      [](PoseGraph& g, std::uint64_t seed, bool shuffle, int file_order_iterations, int max_iterations,
         double time_budget_s, double tol, int patience, const py::object& callback, bool verbose) {
        if (file_order_iterations < 0) throw py::value_error("optimize_sgd: file_order_iterations must be >= 0");
        SgdOptions o;
        o.stop = make_stop(max_iterations, time_budget_s, tol, patience, callback, verbose);
        o.seed = seed, o.shuffle = shuffle, o.file_order_iterations = file_order_iterations;
        return run(g, o, [](PoseGraph& x, const SgdOptions& y) { return optimize_sgd(x, y); });
      },
      py::arg("graph"), py::arg("seed") = 1, py::arg("shuffle") = true,
      py::arg("file_order_iterations") = SgdOptions{}.file_order_iterations, SLAMKIT_STOP_ARGS,
      "Olson's stochastic gradient descent on incremental poses (docs/relaxers.md), in place.");
  m.def(
      "optimize_toro",
      [](PoseGraph& g, std::uint64_t seed, bool shuffle_in_gradient_phase, int max_iterations, double time_budget_s,
         double tol, int patience, const py::object& callback, bool verbose) {
        ToroOptions o;
        o.stop = make_stop(max_iterations, time_budget_s, tol, patience, callback, verbose);
        o.seed = seed, o.shuffle_in_gradient_phase = shuffle_in_gradient_phase;
        return run(g, o, [](PoseGraph& x, const ToroOptions& y) { return optimize_toro(x, y); });
      },
      py::arg("graph"), py::arg("seed") = 1, py::arg("shuffle_in_gradient_phase") = true, SLAMKIT_STOP_ARGS, "TORO: tree-parameterized gradient descent (2D and 3D), in place.");
  m.def(
      "optimize_relaxation",
      [](PoseGraph& g, double over_relaxation, int max_iterations, double time_budget_s, double tol, int patience,
         const py::object& callback, bool verbose) {
        require_finite(over_relaxation, "over_relaxation");
        if (!(over_relaxation > 0 && over_relaxation < 2)) throw py::value_error("over_relaxation must be in (0, 2)");
        RelaxationOptions o;
        o.stop = make_stop(max_iterations, time_budget_s, tol, patience, callback, verbose);
        o.over_relaxation = over_relaxation;
        return run(g, o, [](PoseGraph& x, const RelaxationOptions& y) { return optimize_relaxation(x, y); });
      },
      py::arg("graph"), py::arg("over_relaxation") = 1.0, SLAMKIT_STOP_ARGS,
      "Gauss-Seidel relaxation (Duckett et al.; Howard): each pose re-solved from its neighbours, in place.");
  m.def(
      "optimize_multilevel",
      [](PoseGraph& g, int pre_smoothing, int post_smoothing, int max_cycles, int coarsest_nodes, int max_iterations,
         double time_budget_s, double tol, int patience, const py::object& callback, bool verbose) {
        if (pre_smoothing < 0 || post_smoothing < 0 || max_cycles < 1 || coarsest_nodes < 1)
          throw py::value_error("optimize_multilevel: smoothing >= 0, max_cycles >= 1, coarsest_nodes >= 1");
        MultilevelOptions o;
        o.stop = make_stop(max_iterations, time_budget_s, tol, patience, callback, verbose);
        o.pre_smoothing = pre_smoothing, o.post_smoothing = post_smoothing, o.max_cycles = max_cycles;
        o.coarsest_nodes = coarsest_nodes;
        return run(g, o, [](PoseGraph& x, const MultilevelOptions& y) { return optimize_multilevel(x, y); });
      },
      py::arg("graph"), py::arg("pre_smoothing") = 2, py::arg("post_smoothing") = 2, py::arg("max_cycles") = 20,
      py::arg("coarsest_nodes") = 32, SLAMKIT_STOP_ARGS,
      "Multi-level relaxation (Frese, Larsson, Duckett): multigrid V-cycles per linearization, in place.");
  m.def(
      "optimize_hogman",
      [](PoseGraph& g, int group_size, int max_levels, int threads, int max_iterations, double time_budget_s,
         double tol, int patience, const py::object& callback, bool verbose) {
        if (group_size < 2 || max_levels < 1 || threads < 1)
          throw py::value_error("optimize_hogman: group_size >= 2, max_levels >= 1, threads >= 1");
        HogmanOptions o;
        o.stop = make_stop(max_iterations, time_budget_s, tol, patience, callback, verbose);
        o.group_size = group_size, o.max_levels = max_levels, o.threads = threads;
        return run(g, o, [](PoseGraph& x, const HogmanOptions& y) { return optimize_hogman(x, y); });
      },
      py::arg("graph"), py::arg("group_size") = 8, py::arg("max_levels") = 3, py::arg("threads") = 1,
      SLAMKIT_STOP_ARGS, "HOG-Man: hierarchical optimization on the manifold, top-down, in place.");

  py::class_<HogmanOnlineResult>(m, "HogmanOnlineResult", "HOG-Man grown one pose at a time in file order.")
      .def_property_readonly("graph_size", [](const HogmanOnlineResult& r) { return to_array(r.graph_size); })
      .def_property_readonly("time_per_pose_s", [](const HogmanOnlineResult& r) { return to_array(r.time_per_pose_s); })
      .def_property_readonly("top_solved", [](const HogmanOnlineResult& r) {
        std::vector<int> v(r.top_solved.begin(), r.top_solved.end());
        return to_array(v);
      })
      .def_readonly("final_chi2", &HogmanOnlineResult::final_chi2)
      .def_readonly("total_time_s", &HogmanOnlineResult::total_time_s)
      .def_readonly("levels", &HogmanOnlineResult::levels);
  m.def(
      "hogman_online",
      [](PoseGraph& g, int group_size, int max_levels) {
        if (group_size < 2 || max_levels < 1) throw py::value_error("hogman_online: group_size >= 2, max_levels >= 1");
        HogmanOptions o;
        o.group_size = group_size, o.max_levels = max_levels;
        py::gil_scoped_release release;
        return hogman_online(g, o);
      },
      py::arg("graph"), py::arg("group_size") = 8, py::arg("max_levels") = 3,
      "Online HOG-Man: adds the poses one by one (file order), updating only the affected levels.");

  m.def(
      "compare_backends",
      [](const PoseGraph& g, const std::vector<std::string>& solvers, const std::string& init, double time_budget_s,
         int max_iterations, int threads, bool progress) {
        require_finite(time_budget_s, "time_budget_s");
        if (!(time_budget_s > 0)) throw py::value_error("time_budget_s must be > 0");
        if (max_iterations < 1 || threads < 1) throw py::value_error("max_iterations and threads must be >= 1");
        ComparisonOptions o;
        o.solvers = solvers, o.init = init, o.time_budget_s = time_budget_s;
        o.max_iterations = max_iterations, o.threads = threads, o.progress = progress;
        Comparison c;
        {
          py::gil_scoped_release release;
          c = compare_backends(g, o);
        }
        return comparison_dict(c);
      },
      py::arg("graph"), py::arg("solvers") = ComparisonOptions{}.solvers, py::arg("init") = "odometry",
      py::arg("time_budget_s") = 10.0, py::arg("max_iterations") = 1000, py::arg("threads") = 1,
      py::arg("progress") = false,
      "`slamkit compare`: every back end from the same start (the graph is not changed); a dict with the runs "
      "ranked best first, each with solver, final_chi2, time_total_s, iterations, time_to_reach_s and trace "
      "[(time_s, chi2)].");
}

}  // namespace slamkit::python
