// Bindings of slamkit/factors: the built-in factors, the pose-graph problem builder and
// optimize_pose_graph with the options and results of `slamkit optimize`.
#include <cmath>

#include "bind_callbacks.h"
#include "bind_values.h"
#include "slamkit/core/pose_graph.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/between_factor.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/factors/pose_graph_problem.h"
#include "slamkit/factors/pose_point_factor.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/solvers/pose_graph_init.h"

namespace slamkit::python {
namespace {

using NoisePtr = std::shared_ptr<NoiseModel>;
using KernelPtr = std::shared_ptr<RobustKernel>;

NoisePtr checked_noise(const NoisePtr& noise, int dim) {
  if (!noise) throw py::value_error("noise model is None");
  if (noise->dim() != dim)
    throw py::value_error("noise model has dimension " + std::to_string(noise->dim()) + ", the residual " +
                          std::to_string(dim));
  return noise;
}

Se3ErrorForm parse_se3_form(const std::string& s) {
  if (s == "quaternion") return Se3ErrorForm::kQuaternion;
  if (s == "log") return Se3ErrorForm::kLog;
  throw py::value_error("se3 error form: expected 'quaternion' or 'log', got '" + s + "'");
}

template <class T>
std::shared_ptr<Factor> make_prior(Key key, const T& value, const NoisePtr& noise, const KernelPtr& kernel) {
  return std::make_shared<PriorFactor<T>>(key, value, checked_noise(noise, ManifoldTraits<T>::kTangent), kernel);
}

std::shared_ptr<Factor> prior_factory(Key key, const py::handle& value, const NoisePtr& noise,
                                      const KernelPtr& kernel) {
  if (py::isinstance<SE2>(value)) return make_prior(key, value.cast<SE2>(), noise, kernel);
  if (py::isinstance<SE3>(value)) return make_prior(key, value.cast<SE3>(), noise, kernel);
  if (py::isinstance<SO2>(value)) return make_prior(key, value.cast<SO2>(), noise, kernel);
  if (py::isinstance<SO3>(value)) return make_prior(key, value.cast<SO3>(), noise, kernel);
  const Eigen::VectorXd x = to_vector(value, -1, "value");
  return with_vector_dim(static_cast<int>(x.size()), [&](auto n) -> std::shared_ptr<Factor> {
    using Vec = Eigen::Matrix<double, decltype(n)::value, 1>;
    return make_prior(key, Vec(x), noise, kernel);
  });
}

template <class T>
void bind_prior_class(py::module_& m, const char* name) {
  py::class_<PriorFactor<T>, Factor, std::shared_ptr<PriorFactor<T>>>(m, name, "Prior factor (made by PriorFactor()).")
      .def_property_readonly("measured", [](const PriorFactor<T>& f) { return f.measured(); });
}

PoseGraphProblemOptions problem_options(const py::object& robust, bool loops_only, const std::string& se3_error) {
  PoseGraphProblemOptions p;
  if (py::isinstance<py::str>(robust))
    p.kernel = parse_robust_kernel(robust.cast<std::string>());
  else if (!robust.is_none())
    p.kernel = robust.cast<KernelPtr>();
  p.kernel_on_odometry = !loops_only;
  p.se3_error = parse_se3_form(se3_error);
  return p;
}

// The CLI's --json document of `slamkit optimize`, from the result (keys as cmd_optimize.cpp).
py::dict result_dict(const PoseGraphResult& r, const PoseGraph& g) {
  return py::module_::import("json").attr("loads")(pose_graph_result_to_json(r, g));
}

}  // namespace

void init_factors(py::module_& m) {
  py::class_<BetweenFactorSE2, Factor, std::shared_ptr<BetweenFactorSE2>>(
      m, "BetweenFactorSE2", "e = t2v(Z^-1 Xi^-1 Xj) = [t; theta] (g2o EDGE_SE2).")
      .def(py::init([](Key i, Key j, const SE2& z, const NoisePtr& noise, const KernelPtr& kernel) {
             return std::make_shared<BetweenFactorSE2>(i, j, z, checked_noise(noise, 3), kernel);
           }),
           py::arg("key_i"), py::arg("key_j"), py::arg("measured"), py::arg("noise"), py::arg("kernel") = nullptr)
      .def_property_readonly("measured", &BetweenFactorSE2::measured);
  py::class_<BetweenFactorSE3, Factor, std::shared_ptr<BetweenFactorSE3>>(
      m, "BetweenFactorSE3",
      "form='quaternion': e = [t; q.vec] of Z^-1 Xi^-1 Xj (g2o EDGE_SE3:QUAT); form='log': e = Log(Z^-1 Xi^-1 Xj).")
      .def(py::init([](Key i, Key j, const SE3& z, const NoisePtr& noise, const KernelPtr& kernel,
                       const std::string& form) {
             return std::make_shared<BetweenFactorSE3>(i, j, z, checked_noise(noise, 6), kernel, parse_se3_form(form));
           }),
           py::arg("key_i"), py::arg("key_j"), py::arg("measured"), py::arg("noise"), py::arg("kernel") = nullptr,
           py::arg("form") = "quaternion")
      .def_property_readonly("measured", &BetweenFactorSE3::measured)
      .def_property_readonly("form", [](const BetweenFactorSE3& f) {
        return f.form() == Se3ErrorForm::kLog ? "log" : "quaternion";
      });
  py::class_<PosePointFactor2, Factor, std::shared_ptr<PosePointFactor2>>(
      m, "PosePointFactor2", "Landmark p (Vector2) seen from pose X (SE2): e = X^-1 p - z (g2o EDGE_SE2_XY).")
      .def(py::init([](Key pose, Key point, const py::handle& z, const NoisePtr& noise, const KernelPtr& kernel) {
             return std::make_shared<PosePointFactor2>(pose, point, to_vector(z, 2, "measured"),
                                                       checked_noise(noise, 2), kernel);
           }),
           py::arg("pose_key"), py::arg("point_key"), py::arg("measured"), py::arg("noise"),
           py::arg("kernel") = nullptr);
  py::class_<PosePointFactor3, Factor, std::shared_ptr<PosePointFactor3>>(
      m, "PosePointFactor3",
      "Landmark p (Vector3) seen from pose X (SE3) through sensor offset O: e = (X O)^-1 p - z.")
      .def(py::init([](Key pose, Key point, const py::handle& z, const NoisePtr& noise, const SE3& offset,
                       const KernelPtr& kernel) {
             return std::make_shared<PosePointFactor3>(pose, point, to_vector(z, 3, "measured"), offset,
                                                       checked_noise(noise, 3), kernel);
           }),
           py::arg("pose_key"), py::arg("point_key"), py::arg("measured"), py::arg("noise"),
           py::arg("sensor_offset") = SE3(), py::arg("kernel") = nullptr);
  bind_prior_class<SE2>(m, "PriorFactorSE2");
  bind_prior_class<SE3>(m, "PriorFactorSE3");
  bind_prior_class<SO2>(m, "PriorFactorSO2");
  bind_prior_class<SO3>(m, "PriorFactorSO3");
  bind_prior_class<Eigen::Vector2d>(m, "PriorFactorVector2");
  bind_prior_class<Eigen::Vector3d>(m, "PriorFactorVector3");
  m.def("PriorFactor", &prior_factory, py::arg("key"), py::arg("measured"), py::arg("noise"),
        py::arg("kernel") = nullptr,
        "Unary factor towards measured (SE2/SE3/SO2/SO3: e = Log(z^-1 x); vectors: e = x - z).");

  // ---- pose-graph pipeline ----
  py::class_<InitSummary>(m, "InitSummary", "What the initialization did: requested and used method, time, notes.")
      .def_property_readonly("requested", [](const InitSummary& s) { return std::string(to_string(s.requested)); })
      .def_property_readonly("used", [](const InitSummary& s) { return std::string(to_string(s.used)); })
      .def_readonly("time_s", &InitSummary::time_s)
      .def_readonly("notes", &InitSummary::notes);
  m.def(
      "initialize_pose_graph",
      [](PoseGraph& g, const std::string& method, const py::object& gauge) {
        const std::vector<std::int64_t> ids =
            gauge.is_none() ? gauge_vertices(g) : gauge.cast<std::vector<std::int64_t>>();
        for (std::int64_t id : ids) g.vertex(id);  // InputError for an unknown gauge vertex
        if (ids.empty() && !g.vertices().empty()) throw py::value_error("initialize_pose_graph: empty gauge");
        const InitMethod im = parse_init_method(method);
        py::gil_scoped_release release;
        return initialize_pose_graph(g, im, ids);
      },
      py::arg("graph"), py::arg("method") = "auto", py::arg("gauge") = py::none(),
      "Overwrites the non-gauge estimates: 'none' | 'odometry' | 'spanning-tree' | 'linear' | 'chordal' | 'auto'.");

  py::class_<PoseGraphProblem>(m, "PoseGraphProblem", "A pose graph as a FactorGraph and Values (keys = vertex ids).")
      .def_readonly("graph", &PoseGraphProblem::graph)
      .def_readonly("values", &PoseGraphProblem::values)
      .def_readonly("gauge", &PoseGraphProblem::gauge)
      .def_readonly("notes", &PoseGraphProblem::notes);
  m.def(
      "build_pose_graph_problem",
      [](const PoseGraph& g, const py::object& robust, bool loops_only, const std::string& se3_error) {
        return build_pose_graph_problem(g, problem_options(robust, loops_only, se3_error));
      },
      py::arg("graph"), py::arg("robust") = py::none(), py::arg("robust_loop_closures_only") = false,
      py::arg("se3_error") = "quaternion",
      "Factors and variables of a pose graph; robust: a RobustKernel or 'KERNEL:delta'. "
      "problem.graph and problem.values refer into the returned PoseGraphProblem (optimizing "
      "problem.values changes it; use problem.values.copy() to keep the start).");
  m.def("copy_estimates", &copy_estimates, py::arg("values"), py::arg("graph"),
        "Writes the variables back into the graph's vertex estimates.");

  py::class_<PoseGraphResult>(m, "PoseGraphResult", "What optimize_pose_graph did (as `slamkit optimize` prints).")
      .def_readonly("init", &PoseGraphResult::init)
      .def_readonly("summary", &PoseGraphResult::summary)
      .def_readonly("input_chi2", &PoseGraphResult::input_chi2)
      .def_readonly("chi2_after_init", &PoseGraphResult::chi2_after_init)
      .def_readonly("final_chi2", &PoseGraphResult::final_chi2, "g2o chi2 (no robust kernel) of the result.")
      .def_readonly("time_ordering_s", &PoseGraphResult::time_ordering_s)
      .def_readonly("time_total_s", &PoseGraphResult::time_total_s)
      .def_readonly("notes", &PoseGraphResult::notes)
      .def_readonly("calibration", &PoseGraphResult::calibration,
                    "CalibrationReport: estimates with marginal sigmas when the graph has calibration variables.")
      .def("__repr__", [](const PoseGraphResult& r) {
        return "PoseGraphResult(final_chi2=" + std::to_string(r.final_chi2) + ", " +
               std::string(to_string(r.summary.termination)) + ")";
      });

  m.def(
      "optimize_pose_graph",
      [](PoseGraph& g, const std::string& solver, const std::string& init, int max_iterations,
         const py::object& robust, bool loops_only, int threads, int blas_threads, double function_tolerance,
         double gradient_tolerance, double parameter_tolerance, const std::string& linear_solver,
         const std::string& ordering, const std::string& se3_error, const std::string& calibrate,
         const py::object& callback, bool verbose, bool as_dict, double keep_estimates_chi2_per_dof) -> py::object {
        PoseGraphOptimizerOptions o;
        o.init = parse_init_method(init);
        if (!(std::isfinite(keep_estimates_chi2_per_dof) && keep_estimates_chi2_per_dof >= 0.0))
          throw py::value_error("keep_estimates_chi2_per_dof must be finite and non-negative");
        o.keep_estimates_chi2_per_dof = keep_estimates_chi2_per_dof;
        o.optimizer.algorithm = parse_algorithm(solver);
        o.optimizer.max_iterations = max_iterations;
        o.optimizer.num_threads = threads;
        o.optimizer.blas_threads = blas_threads;
        o.optimizer.function_tolerance = function_tolerance;
        o.optimizer.gradient_tolerance = gradient_tolerance;
        o.optimizer.parameter_tolerance = parameter_tolerance;
        o.optimizer.linear_solver = parse_sparse_backend(linear_solver);
        o.optimizer.ordering = parse_ordering(ordering);
        o.problem = problem_options(robust, loops_only, se3_error);
        o.problem.calibration = parse_calibrate_option(calibrate);
        validate_optimizer_options(o.optimizer);
        install_python_callback(o.optimizer, callback, verbose);
        PoseGraphResult r;
        {
          py::gil_scoped_release release;
          r = optimize_pose_graph(g, o);
        }
        r.summary.options.callback = nullptr;
        if (as_dict) return result_dict(r, g);
        return py::cast(std::move(r));
      },
      py::arg("graph"), py::arg("solver") = "gn", py::arg("init") = "auto", py::arg("max_iterations") = 100,
      py::arg("robust") = py::none(), py::arg("robust_loop_closures_only") = false, py::arg("threads") = 0,
      py::arg("blas_threads") = 1, py::arg("function_tolerance") = 1e-5, py::arg("gradient_tolerance") = 1e-10,
      py::arg("parameter_tolerance") = 1e-8, py::arg("linear_solver") = "auto", py::arg("ordering") = "auto",
      py::arg("se3_error") = "quaternion", py::arg("calibrate") = "auto", py::arg("callback") = py::none(),
      py::arg("verbose") = false, py::arg("as_dict") = false, py::arg("keep_estimates_chi2_per_dof") = 1.0,
      "The whole pipeline of `slamkit optimize` (gauge, ordering, initialization, optimization) with the same "
      "options and defaults; the graph's estimates are replaced by the result. The GIL is released while it "
      "runs. Returns a PoseGraphResult, or with as_dict=True the CLI's --json document as a dict.");
  m.def("pose_graph_result_dict", &result_dict, py::arg("result"), py::arg("graph"),
        "The CLI's --json document (without file/label/load time) of a PoseGraphResult.");
}

}  // namespace slamkit::python
