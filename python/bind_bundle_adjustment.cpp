// Bindings of bundle adjustment: BalProblem (cameras N×9 [ω, t, f, k1, k2], points M×3,
// observations as index and pixel arrays), the BAL reader/writer, the sim:ba generator and
// optimize_bundle_adjustment (points eliminated by the Schur complement), as
// `slamkit optimize --format bal` runs it.
#include <sstream>

#include "bind_callbacks.h"
#include "slamkit/core/bal_problem.h"
#include "slamkit/core/robust_kernel.h"
#include "slamkit/factors/bundle_adjustment.h"
#include "slamkit/io/bal_io.h"
#include "slamkit/sim/ba_generator.h"

namespace slamkit::python {
namespace {

py::array_t<double> cameras_array(const BalProblem& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.cameras.size()), py::ssize_t{9}});
  auto u = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.cameras.size(); ++i)
    for (int k = 0; k < 9; ++k) u(i, k) = p.cameras[i](k);
  return a;
}

py::array_t<double> points_array(const BalProblem& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.points.size()), py::ssize_t{3}});
  auto u = a.mutable_unchecked<2>();
  for (std::size_t j = 0; j < p.points.size(); ++j)
    for (int k = 0; k < 3; ++k) u(j, k) = p.points[j](k);
  return a;
}

// Replacing cameras or points keeps their count: the observations index them.
void set_cameras(BalProblem& p, const py::handle& a) {
  const RowMatrixXd m = to_matrix(a, static_cast<Eigen::Index>(p.cameras.size()), 9, "cameras");
  for (std::size_t i = 0; i < p.cameras.size(); ++i) p.cameras[i] = m.row(static_cast<Eigen::Index>(i)).transpose();
}

void set_points(BalProblem& p, const py::handle& a) {
  const RowMatrixXd m = to_matrix(a, static_cast<Eigen::Index>(p.points.size()), 3, "points");
  for (std::size_t j = 0; j < p.points.size(); ++j) p.points[j] = m.row(static_cast<Eigen::Index>(j)).transpose();
}

// A problem from arrays, with every index checked (the reader's rules).
BalProblem make_problem(const py::handle& cameras, const py::handle& points, const py::handle& camera_index,
                        const py::handle& point_index, const py::handle& pixels) {
  BalProblem p;
  p.source = "python";
  const RowMatrixXd c = to_matrix(cameras, -1, 9, "cameras");
  const RowMatrixXd x = to_matrix(points, -1, 3, "points");
  const py::array_t<long long, py::array::forcecast> ci = py::array_t<long long, py::array::forcecast>::ensure(camera_index);
  const py::array_t<long long, py::array::forcecast> pi = py::array_t<long long, py::array::forcecast>::ensure(point_index);
  if (!ci || !pi || ci.ndim() != 1 || pi.ndim() != 1)
    throw py::value_error("camera_index, point_index: expected 1-D integer arrays");
  const RowMatrixXd z = to_matrix(pixels, ci.shape(0), 2, "pixels");
  if (pi.shape(0) != ci.shape(0)) throw py::value_error("camera_index and point_index differ in length");
  if (c.rows() == 0 || x.rows() == 0 || ci.shape(0) == 0) throw py::value_error("a BAL problem needs cameras, points and observations");
  for (Eigen::Index i = 0; i < c.rows(); ++i) p.cameras.push_back(c.row(i).transpose());
  for (Eigen::Index j = 0; j < x.rows(); ++j) p.points.push_back(x.row(j).transpose());
  for (py::ssize_t k = 0; k < ci.shape(0); ++k) {
    const long long cam = ci.at(k), pt = pi.at(k);
    if (cam < 0 || cam >= c.rows())
      throw py::value_error("camera_index[" + std::to_string(k) + "] = " + std::to_string(cam) + " is out of range");
    if (pt < 0 || pt >= x.rows())
      throw py::value_error("point_index[" + std::to_string(k) + "] = " + std::to_string(pt) + " is out of range");
    p.observations.push_back({static_cast<int>(cam), static_cast<int>(pt), z.row(k).transpose()});
  }
  return p;
}

BaSimOptions ba_sim_options(const py::kwargs& kw) {
  py::object tmp = py::cast(BaSimOptions{});
  set_from_kwargs(tmp, kw);
  return tmp.cast<BaSimOptions>();
}

}  // namespace

void init_bundle_adjustment(py::module_& m) {
  py::class_<BalProblem>(m, "BalProblem",
                         "A bundle-adjustment problem in the BAL camera model (docs/bundle_adjustment.md): "
                         "cameras N×9 [ω (angle-axis), t, f, k1, k2], points M×3, observations (camera, point, "
                         "pixel). BalProblem(cameras, points, camera_index, point_index, pixels).")
      .def(py::init(&make_problem), py::arg("cameras"), py::arg("points"), py::arg("camera_index"),
           py::arg("point_index"), py::arg("pixels"))
      .def_property_readonly("num_cameras", &BalProblem::num_cameras)
      .def_property_readonly("num_points", &BalProblem::num_points)
      .def_property_readonly("num_observations", &BalProblem::num_observations)
      .def_readonly("source", &BalProblem::source)
      .def_property("cameras", &cameras_array, &set_cameras, "N×9 copy; assign an array of the same shape to change.")
      .def_property("points", &points_array, &set_points, "M×3 copy; assign an array of the same shape to change.")
      .def_property_readonly("camera_index", [](const BalProblem& p) {
        std::vector<int> v;
        for (const BalObservation& o : p.observations) v.push_back(o.camera);
        return to_array(v);
      })
      .def_property_readonly("point_index", [](const BalProblem& p) {
        std::vector<int> v;
        for (const BalObservation& o : p.observations) v.push_back(o.point);
        return to_array(v);
      })
      .def_property_readonly("pixels", [](const BalProblem& p) {
        py::array_t<double> a({static_cast<py::ssize_t>(p.observations.size()), py::ssize_t{2}});
        auto u = a.mutable_unchecked<2>();
        for (std::size_t k = 0; k < p.observations.size(); ++k) u(k, 0) = p.observations[k].pixel.x(), u(k, 1) = p.observations[k].pixel.y();
        return a;
      })
      .def("cost", &bal_cost, "½ Σ ‖u − z‖² (Ceres' convention).")
      .def("copy", [](const BalProblem& p) { return BalProblem(p); }, "A deep copy.")
      .def("__repr__", [](const BalProblem& p) {
        return "BalProblem(cameras=" + std::to_string(p.num_cameras()) + ", points=" + std::to_string(p.num_points()) +
               ", observations=" + std::to_string(p.num_observations()) + ")";
      });

  m.def(
      "read_bal",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return read_bal(path);
      },
      py::arg("path"), "Reads a BAL file; raises InputError naming the file, line and field.");
  m.def(
      "bal_from_string",
      [](const std::string& text, const std::string& source) {
        std::istringstream in(text);
        return read_bal(in, source);
      },
      py::arg("text"), py::arg("source") = "<string>", "Parses BAL text (source names it in errors).");
  m.def(
      "write_bal", [](const BalProblem& p, const std::string& path) { write_bal(path, p); }, py::arg("problem"),
      py::arg("path"), "Writes a BAL file (round-trip exact), replacing it atomically (as write_pose_graph).");
  m.def("bal_to_string", &bal_to_string, py::arg("problem"), "The BAL text write_bal writes.");
  m.def("validate_bal_geometry", [](const BalProblem& p) { validate_bal_geometry(p); }, py::arg("problem"),
        "Raises InputError when a predicted pixel is not finite (as `slamkit optimize` checks).");
  m.def("normalize_bal", &normalize_bal, py::arg("problem"),
        "Median-centres and scales the scene as the BAL tools do (costs unchanged); returns the scale.");
  m.def(
      "perturb_bal",
      [](BalProblem& p, double rotation_sigma, double translation_sigma, double point_sigma, std::uint64_t seed) {
        for (double v : {rotation_sigma, translation_sigma, point_sigma}) {
          require_finite(v, "perturb_bal sigma");
          if (v < 0) throw py::value_error("perturb_bal: sigmas must be >= 0");
        }
        perturb_bal(p, {rotation_sigma, translation_sigma, point_sigma, seed});
      },
      py::arg("problem"), py::arg("rotation_sigma") = 0.0, py::arg("translation_sigma") = 0.0,
      py::arg("point_sigma") = 0.0, py::arg("seed") = 1, "Gaussian perturbation of the estimates (in place).");
  m.def(
      "generate_ba_problem",
      [](bool truth, const py::kwargs& kw) -> py::object {
        const BaSimOptions o = ba_sim_options(kw);
        BalProblem t, p;
        {
          py::gil_scoped_release release;
          p = generate_ba_problem(o, truth ? &t : nullptr);
        }
        if (truth) return py::make_tuple(std::move(p), std::move(t));
        return py::cast(std::move(p));
      },
      py::arg("ground_truth") = false,
      "The sim:ba street scene (keywords cameras, points, seed, noise, min_track, max_track, spacing, ...); "
      "with ground_truth=True returns (problem, truth).");
  py::class_<BaSimOptions>(m, "BaSimOptions", "Options of generate_ba_problem (keywords of the same names).")
      .def(py::init([](const py::kwargs& kw) { return ba_sim_options(kw); }))
      .def_readwrite("cameras", &BaSimOptions::cameras)
      .def_readwrite("points", &BaSimOptions::points)
      .def_readwrite("seed", &BaSimOptions::seed)
      .def_readwrite("noise", &BaSimOptions::noise)
      .def_readwrite("min_track", &BaSimOptions::min_track)
      .def_readwrite("max_track", &BaSimOptions::max_track)
      .def_readwrite("spacing", &BaSimOptions::spacing)
      .def_readwrite("rotation_start_sigma", &BaSimOptions::rotation_start_sigma)
      .def_readwrite("centre_start_sigma", &BaSimOptions::centre_start_sigma)
      .def_readwrite("point_start_sigma", &BaSimOptions::point_start_sigma)
      .def_readwrite("focal_start_sigma", &BaSimOptions::focal_start_sigma);

  py::class_<BundleAdjustmentResult>(m, "BundleAdjustmentResult", "What optimize_bundle_adjustment did.")
      .def_readonly("summary", &BundleAdjustmentResult::summary)
      .def_readonly("initial_cost", &BundleAdjustmentResult::initial_cost, "½ Σ ρ(‖r‖²) at the start.")
      .def_readonly("final_cost", &BundleAdjustmentResult::final_cost, "½ Σ ρ(‖r‖²) at the end.")
      .def_readonly("time_build_s", &BundleAdjustmentResult::time_build_s)
      .def("__repr__", [](const BundleAdjustmentResult& r) {
        return "BundleAdjustmentResult(initial_cost=" + std::to_string(r.initial_cost) +
               ", final_cost=" + std::to_string(r.final_cost) + ")";
      });
  m.def(
      "bundle_adjustment_options",
      [] { return BundleAdjustmentOptions::default_optimizer(); },
      "The OptimizerOptions optimize_bundle_adjustment starts from (LM with Ceres' defaults, points Schur-eliminated).");
  m.def(
      "optimize_bundle_adjustment",
      [](BalProblem& p, const py::object& robust, const py::object& options, const py::object& callback,
         bool verbose) {
        BundleAdjustmentOptions o;
        if (!options.is_none()) o.optimizer = options.cast<OptimizerOptions>();
        if (py::isinstance<py::str>(robust))
          o.kernel = parse_robust_kernel(robust.cast<std::string>());
        else if (!robust.is_none())
          o.kernel = robust.cast<std::shared_ptr<RobustKernel>>();
        validate_optimizer_options(o.optimizer);
        install_python_callback(o.optimizer, callback, verbose);
        BundleAdjustmentResult r;
        {
          py::gil_scoped_release release;
          r = optimize_bundle_adjustment(p, o);
        }
        r.summary.options.callback = nullptr;
        return r;
      },
      py::arg("problem"), py::arg("robust") = py::none(), py::arg("options") = py::none(),
      py::arg("callback") = py::none(), py::arg("verbose") = false,
      "Bundle adjustment of the problem in place (cameras and points), as `slamkit optimize --format bal`: "
      "robust a RobustKernel or 'KERNEL:delta'; options an OptimizerOptions (default "
      "bundle_adjustment_options()). The GIL is released while it runs.");
}

}  // namespace slamkit::python
