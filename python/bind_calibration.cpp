// Bindings of calibration inside the pose graph (docs/calibration.md): the CalibrationReport
// that optimize_pose_graph(calibrate=...) returns, and the sim:calib2d / sim:calib3d problems
// with their true parameters.
#include "bind_common.h"
#include "slamkit/factors/calibration_problem.h"
#include "slamkit/sim/calibration_generator.h"

namespace slamkit::python {
namespace {

CalibrationSimOptions calibration_sim_options(const py::kwargs& kw) {
  py::object tmp = py::cast(CalibrationSimOptions{});
  set_from_kwargs(tmp, kw);
  return tmp.cast<CalibrationSimOptions>();
}

}  // namespace

void init_calibration(py::module_& m) {
  py::class_<CalibrationParameterEstimate>(m, "CalibrationParameterEstimate",
                                           "One estimated calibration parameter with its marginal sigma.")
      .def_readonly("name", &CalibrationParameterEstimate::name, "e.g. 'odometry[1001].baseline'")
      .def_readonly("value", &CalibrationParameterEstimate::value)
      .def_readonly("sigma", &CalibrationParameterEstimate::sigma, "NaN when unobservable.")
      .def_readonly("observable", &CalibrationParameterEstimate::observable)
      .def_readonly("excitation", &CalibrationParameterEstimate::excitation)
      .def_readonly("reason", &CalibrationParameterEstimate::reason)
      .def("__repr__", [](const CalibrationParameterEstimate& p) {
        return "CalibrationParameterEstimate(" + p.name + "=" + std::to_string(p.value) +
               ", sigma=" + std::to_string(p.sigma) + ")";
      });
  py::class_<CalibrationReport>(m, "CalibrationReport", "The calibration estimates of an optimization.")
      .def_readonly("parameters", &CalibrationReport::parameters)
      .def_readonly("warnings", &CalibrationReport::warnings)
      .def_readonly("held", &CalibrationReport::held, "Parameters held at their initial value (unobservable).")
      .def_readonly("covariance", &CalibrationReport::covariance, "Joint marginal covariance of `parameters`.")
      .def("as_dict", [](const CalibrationReport& r) {
        py::dict d;
        for (const CalibrationParameterEstimate& p : r.parameters) d[py::str(p.name)] = py::make_tuple(p.value, p.sigma);
        return d;
      }, "{name: (value, sigma)}");

  py::class_<CalibrationSimOptions>(m, "CalibrationSimOptions",
                                    "Options of generate_calibration_problem (keywords of the same names).")
      .def(py::init([](const py::kwargs& kw) { return calibration_sim_options(kw); }))
      .def_readwrite("world", &CalibrationSimOptions::world, "'calib2d' or 'calib3d'")
      .def_readwrite("path", &CalibrationSimOptions::path, "calib2d: 'figure' or 'line'")
      .def_readwrite("odometry", &CalibrationSimOptions::odometry, "calib2d: 'differential' or 'linear'")
      .def_readwrite("laps", &CalibrationSimOptions::laps)
      .def_readwrite("step", &CalibrationSimOptions::step)
      .def_readwrite("bias", &CalibrationSimOptions::bias)
      .def_readwrite("nominal_baseline", &CalibrationSimOptions::nominal_baseline)
      .def_readwrite("odometry_sigma_t", &CalibrationSimOptions::odometry_sigma_t)
      .def_readwrite("odometry_sigma_r", &CalibrationSimOptions::odometry_sigma_r)
      .def_readwrite("scan_sigma_t", &CalibrationSimOptions::scan_sigma_t)
      .def_readwrite("scan_sigma_r", &CalibrationSimOptions::scan_sigma_r)
      .def_readwrite("loop_radius", &CalibrationSimOptions::loop_radius)
      .def_readwrite("seed", &CalibrationSimOptions::seed);

  m.def(
      "generate_calibration_problem",
      [](bool ground_truth, const py::kwargs& kw) -> py::object {
        const CalibrationSimOptions o = calibration_sim_options(kw);
        CalibrationTruth truth;
        PoseGraph g, true_graph;
        {
          py::gil_scoped_release release;
          g = generate_calibration_problem(o, &truth, ground_truth ? &true_graph : nullptr);
        }
        py::dict t;
        for (const auto& [name, value] : truth) t[py::str(name)] = value;
        if (ground_truth) return py::make_tuple(std::move(g), t, std::move(true_graph));
        return py::make_tuple(std::move(g), t);
      },
      py::arg("ground_truth") = false,
      "A synthetic calibration problem (keywords world='calib2d'|'calib3d', laps, bias, seed, path, odometry, ...) "
      "with its true calibration: returns (graph, truth {name: value}), or (graph, truth, true_graph) with "
      "ground_truth=True. Optimize it with optimize_pose_graph(graph, calibrate='auto').");
}

}  // namespace slamkit::python
