// Bindings of slamkit/solvers: OptimizerOptions (keywords with the C++ defaults, enums as
// the CLI's strings), Optimizer (the GIL is released while it runs), Summary and
// IterationSummary.
#include <pybind11/functional.h>

#include <iostream>

#include "bind_callbacks.h"
#include "slamkit/solvers/optimizer.h"
#include "slamkit/solvers/summary.h"

namespace slamkit::python {

std::shared_ptr<py::object> share_python_object(py::object obj) {
  return std::shared_ptr<py::object>(new py::object(std::move(obj)), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
}

void install_python_callback(OptimizerOptions& o, const py::object& user_callback, bool verbose) {
  if (user_callback.is_none() && !verbose) return;
  if (!user_callback.is_none() && !PyCallable_Check(user_callback.ptr()))
    throw py::type_error("callback must be callable");
  auto cb = share_python_object(user_callback);
  const Algorithm algorithm = o.algorithm;
  o.callback = [cb, verbose, algorithm](const IterationSummary& it) {
    py::gil_scoped_acquire gil;
    if (verbose) {
      py::object out = py::module_::import("sys").attr("stdout");
      if (it.iteration == 0) out.attr("write")(Summary::progress_header() + "\n");
      out.attr("write")(Summary::progress_line(it, algorithm) + "\n");
      out.attr("flush")();
    }
    if (cb->is_none()) return true;
    const py::object r = (*cb)(it);  // a Python exception propagates out of optimize()
    return r.is_none() || r.cast<bool>();
  };
}

namespace {

const std::vector<const char*> kOptionFields = {
    "algorithm", "max_iterations", "function_tolerance", "gradient_tolerance", "parameter_tolerance", "gn_patience",
    "lm_initial_lambda", "lm_diagonal_scaling", "lm_max_lambda", "tr_initial_radius", "tr_increase_threshold",
    "tr_decrease_threshold", "tr_increase_factor", "tr_decrease_factor", "tr_accept_threshold",
    "tr_max_inner_solves", "tr_min_radius", "dogleg_initial_radius", "dogleg_accept_threshold",
    "dogleg_min_radius", "linear_solver", "ordering", "num_threads", "blas_threads"};

py::dict summary_dict(const Summary& s) {
  return py::module_::import("json").attr("loads")(s.to_json());
}

}  // namespace

void validate_optimizer_options(const OptimizerOptions& o) {
  const double values[] = {o.function_tolerance, o.gradient_tolerance, o.parameter_tolerance, o.lm_initial_lambda,
                           o.lm_max_lambda, o.tr_initial_radius, o.tr_increase_threshold, o.tr_decrease_threshold,
                           o.tr_increase_factor, o.tr_decrease_factor, o.tr_accept_threshold, o.tr_min_radius,
                           o.dogleg_initial_radius, o.dogleg_accept_threshold, o.dogleg_min_radius};
  for (double v : values)
    if (!std::isfinite(v) || v < 0.0) throw py::value_error("optimizer options: tolerances, radii and factors must be finite and >= 0");
  // More threads than this is a typo, and spawning them would stall the machine.
  if (o.num_threads > 1024 || o.blas_threads > 1024) throw py::value_error("optimizer options: at most 1024 threads");
}

OptimizerOptions optimizer_options_from_kwargs(const py::kwargs& kwargs) {
  py::object tmp = py::cast(OptimizerOptions{});
  set_from_kwargs(tmp, kwargs);
  return tmp.cast<OptimizerOptions>();
}

void init_solvers(py::module_& m) {
  py::class_<OptimizerOptions> opt(
      m, "OptimizerOptions",
      "Options of the nonlinear least-squares Optimizer; every keyword defaults to the C++ default. "
      "algorithm: 'gn' | 'lm' | 'tr-lm' | 'dogleg'; linear_solver: 'auto' | 'cholmod' | 'eigen'; "
      "ordering: 'auto' | 'amd' | 'metis' | 'nesdis' | 'natural'.");
  opt.def(py::init([](const py::kwargs& kw) { return optimizer_options_from_kwargs(kw); }))
      .def_property(
          "algorithm", [](const OptimizerOptions& o) { return std::string(to_string(o.algorithm)); },
          [](OptimizerOptions& o, const std::string& s) { o.algorithm = parse_algorithm(s); })
      .def_readwrite("max_iterations", &OptimizerOptions::max_iterations)
      .def_readwrite("function_tolerance", &OptimizerOptions::function_tolerance,
                     "Stop when a step changes the cost by less than this fraction of it.")
      .def_readwrite("gradient_tolerance", &OptimizerOptions::gradient_tolerance, "Stop when max|g_i| < this.")
      .def_readwrite("parameter_tolerance", &OptimizerOptions::parameter_tolerance,
                     "Stop when ||delta|| <= tol (||x|| + tol).")
      .def_readwrite("gn_patience", &OptimizerOptions::gn_patience,
                     "Gauss-Newton falls back to LM after this many non-improving steps (0: pure GN).")
      .def_readwrite("lm_initial_lambda", &OptimizerOptions::lm_initial_lambda)
      .def_readwrite("lm_diagonal_scaling", &OptimizerOptions::lm_diagonal_scaling)
      .def_readwrite("lm_max_lambda", &OptimizerOptions::lm_max_lambda)
      .def_readwrite("tr_initial_radius", &OptimizerOptions::tr_initial_radius)
      .def_readwrite("tr_increase_threshold", &OptimizerOptions::tr_increase_threshold)
      .def_readwrite("tr_decrease_threshold", &OptimizerOptions::tr_decrease_threshold)
      .def_readwrite("tr_increase_factor", &OptimizerOptions::tr_increase_factor)
      .def_readwrite("tr_decrease_factor", &OptimizerOptions::tr_decrease_factor)
      .def_readwrite("tr_accept_threshold", &OptimizerOptions::tr_accept_threshold)
      .def_readwrite("tr_max_inner_solves", &OptimizerOptions::tr_max_inner_solves)
      .def_readwrite("tr_min_radius", &OptimizerOptions::tr_min_radius)
      .def_readwrite("dogleg_initial_radius", &OptimizerOptions::dogleg_initial_radius)
      .def_readwrite("dogleg_accept_threshold", &OptimizerOptions::dogleg_accept_threshold)
      .def_readwrite("dogleg_min_radius", &OptimizerOptions::dogleg_min_radius)
      .def_property(
          "linear_solver", [](const OptimizerOptions& o) { return std::string(to_string(o.linear_solver)); },
          [](OptimizerOptions& o, const std::string& s) { o.linear_solver = parse_sparse_backend(s); })
      .def_property(
          "ordering", [](const OptimizerOptions& o) { return std::string(to_string(o.ordering)); },
          [](OptimizerOptions& o, const std::string& s) { o.ordering = parse_ordering(s); })
      .def_readwrite("num_threads", &OptimizerOptions::num_threads, "Linearization threads (<= 0: all cores).")
      .def_readwrite("blas_threads", &OptimizerOptions::blas_threads,
                     "BLAS threads in the factorization (1 keeps results bit-identical).")
      .def("__repr__", [](const py::object& self) { return repr_from_fields(self, "OptimizerOptions", kOptionFields); });

  py::class_<IterationSummary>(m, "IterationSummary", "One iteration of a run (entry 0: the initial state).")
      .def_readonly("iteration", &IterationSummary::iteration)
      .def_readonly("cost", &IterationSummary::cost)
      .def_readonly("cost_change", &IterationSummary::cost_change)
      .def_readonly("gradient_norm", &IterationSummary::gradient_norm)
      .def_readonly("step_norm", &IterationSummary::step_norm)
      .def_readonly("rho", &IterationSummary::rho)
      .def_readonly("damping", &IterationSummary::damping)
      .def_readonly("linear_solves", &IterationSummary::linear_solves)
      .def_readonly("accepted", &IterationSummary::accepted)
      .def_readonly("linear_solver_time_s", &IterationSummary::linear_solver_time_s)
      .def_readonly("iteration_time_s", &IterationSummary::iteration_time_s)
      .def_readonly("cumulative_time_s", &IterationSummary::cumulative_time_s)
      .def("__repr__", [](const IterationSummary& it) {
        return "IterationSummary(iteration=" + std::to_string(it.iteration) + ", cost=" + std::to_string(it.cost) +
               ", accepted=" + (it.accepted ? "True" : "False") + ")";
      });

  py::class_<Summary>(m, "Summary", "What an optimization did and why it stopped.")
      .def_readonly("options", &Summary::options)
      .def_readonly("linear_solver", &Summary::linear_solver)
      .def_readonly("linear_solver_is_fallback", &Summary::linear_solver_is_fallback)
      .def_readonly("ordering", &Summary::ordering)
      .def_readonly("threads", &Summary::threads)
      .def_readonly("blas_threads", &Summary::blas_threads)
      .def_readonly("blas", &Summary::blas)
      .def_readonly("thread_backend", &Summary::thread_backend)
      .def_readonly("num_variables", &Summary::num_variables)
      .def_readonly("num_fixed", &Summary::num_fixed)
      .def_readonly("num_factors", &Summary::num_factors)
      .def_readonly("num_residuals", &Summary::num_residuals)
      .def_readonly("tangent_dim", &Summary::tangent_dim)
      .def_readonly("factor_nnz", &Summary::factor_nnz)
      .def_readonly("factor_flops", &Summary::factor_flops)
      .def_readonly("initial_cost", &Summary::initial_cost)
      .def_readonly("final_cost", &Summary::final_cost)
      .def_readonly("iterations", &Summary::iterations)
      .def_readonly("accepted_steps", &Summary::accepted_steps)
      .def_readonly("linear_solves", &Summary::linear_solves)
      .def_readonly("fallback_iteration", &Summary::fallback_iteration)
      .def_property_readonly("termination", [](const Summary& s) { return std::string(to_string(s.termination)); })
      .def_readonly("message", &Summary::message)
      .def("success", &Summary::success, "Converged, or hit max_iterations with a finite cost.")
      .def_readonly("time_total_s", &Summary::time_total_s)
      .def_readonly("time_setup_s", &Summary::time_setup_s)
      .def_readonly("time_analyze_s", &Summary::time_analyze_s)
      .def_readonly("time_linearize_s", &Summary::time_linearize_s)
      .def_readonly("time_evaluate_s", &Summary::time_evaluate_s)
      .def_readonly("time_linear_solver_s", &Summary::time_linear_solver_s)
      .def_readonly("trace", &Summary::trace)
      .def_property_readonly(
          "costs",
          [](const Summary& s) {
            std::vector<double> c;
            for (const auto& it : s.trace) c.push_back(it.cost);
            return to_array(c);
          },
          "Cost after every iteration (entry 0: initial) as an array.")
      .def("report", &Summary::report, "The full human-readable report.")
      .def("to_json", &Summary::to_json, "The CLI's --json document as a string.")
      .def("to_dict", &summary_dict, "The CLI's --json document as a dict.")
      .def("__repr__", [](const Summary& s) {
        return "Summary(" + std::string(to_string(s.termination)) + ", initial_cost=" + std::to_string(s.initial_cost) +
               ", final_cost=" + std::to_string(s.final_cost) + ", iterations=" + std::to_string(s.iterations) + ")";
      });

  py::class_<Optimizer>(m, "Optimizer",
                        "Sparse nonlinear least squares on manifolds (Gauss-Newton, Levenberg-Marquardt, "
                        "trust-region LM, dogleg). Optimizer(options) or Optimizer(algorithm='lm', ...).")
      .def(py::init([](const py::object& options, const py::kwargs& kw) {
             if (options.is_none()) return Optimizer(optimizer_options_from_kwargs(kw));
             if (kw.size() > 0) throw py::type_error("Optimizer: give options or keywords, not both");
             return Optimizer(options.cast<OptimizerOptions>());
           }),
           py::arg("options") = py::none())
      .def_property_readonly("options", &Optimizer::options)
      .def(
          "optimize",
          [](const Optimizer& opt, const FactorGraph& graph, Values& values, const py::object& callback,
             bool verbose) {
            OptimizerOptions o = opt.options();
            validate_optimizer_options(o);
            install_python_callback(o, callback, verbose);
            Summary s;
            {
              py::gil_scoped_release release;
              s = Optimizer(o).optimize(graph, values);
            }
            s.options.callback = nullptr;
            return s;
          },
          py::arg("graph"), py::arg("values"), py::arg("callback") = py::none(), py::arg("verbose") = false,
          "Optimizes values in place and returns the Summary. The GIL is released while it runs. "
          "callback(IterationSummary) is called after every iteration (return False to stop); "
          "verbose prints the per-iteration progress lines.");
}

}  // namespace slamkit::python
