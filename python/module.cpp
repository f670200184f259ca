// The `slamkit` Python module: exception types, shared conversion helpers, and the
// registration of every bound library module (one binding file per module).
#include <pybind11/pybind11.h>

#include <sstream>

#include "bind_common.h"
#include "slamkit/core/error.h"
#include "slamkit/linear/blas_runtime.h"

namespace slamkit::python {

RowMatrixXd to_matrix(const py::handle& obj, Eigen::Index rows, Eigen::Index cols, const char* what, bool finite) {
  py::array_t<double, py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::forcecast>::ensure(obj);
  } catch (const py::error_already_set&) {
    a = py::array_t<double, py::array::forcecast>();
  }
  if (!a) throw py::value_error(std::string(what) + ": expected a float array");
  Eigen::Index r = 0, c = 0;
  if (a.ndim() == 0) {
    r = 1, c = 1;
  } else if (a.ndim() == 1) {
    r = a.shape(0), c = 1;
    if (rows == 1 && cols != 1) std::swap(r, c);  // a 1-D array where a row is wanted
  } else if (a.ndim() == 2) {
    r = a.shape(0), c = a.shape(1);
  } else {
    throw py::value_error(std::string(what) + ": expected a 1-D or 2-D array, got " + std::to_string(a.ndim()) +
                          " dimensions");
  }
  if ((rows >= 0 && r != rows) || (cols >= 0 && c != cols)) {
    std::ostringstream os;
    os << what << ": expected shape (" << (rows < 0 ? std::string("N") : std::to_string(rows)) << ", "
       << (cols < 0 ? std::string("M") : std::to_string(cols)) << "), got (" << r << ", " << c << ")";
    throw py::value_error(os.str());
  }
  RowMatrixXd m(r, c);
  if (a.ndim() == 0) {
    m(0, 0) = *a.data();
  } else if (a.ndim() == 1) {
    auto u = a.unchecked<1>();
    for (Eigen::Index k = 0; k < r * c; ++k) m.data()[k] = u(k);
  } else {
    auto u2 = a.unchecked<2>();
    for (Eigen::Index i = 0; i < r; ++i)
      for (Eigen::Index j = 0; j < c; ++j) m(i, j) = u2(i, j);
  }
  if (finite) require_finite(m, what);
  return m;
}

Eigen::VectorXd to_vector(const py::handle& obj, Eigen::Index n, const char* what, bool finite) {
  const RowMatrixXd m = to_matrix(obj, -1, -1, what, finite);
  if (m.cols() != 1 && m.rows() != 1)
    throw py::value_error(std::string(what) + ": expected a vector, got a " + std::to_string(m.rows()) + "x" +
                          std::to_string(m.cols()) + " array");
  Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(m.data(), m.size());
  if (n >= 0 && v.size() != n)
    throw py::value_error(std::string(what) + ": expected length " + std::to_string(n) + ", got " +
                          std::to_string(v.size()));
  return v;
}

RowMatrixXd to_rows(const py::handle& obj, Eigen::Index cols, const char* what, bool allow_single) {
  py::array a = py::array::ensure(obj);
  if (a && a.ndim() == 1 && allow_single) return to_matrix(obj, 1, cols, what);
  return to_matrix(obj, -1, cols, what);
}

py::array_t<double> to_array(const std::vector<Eigen::Vector3d>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  auto u = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int j = 0; j < 3; ++j) u(i, j) = v[i](j);
  return a;
}

void set_from_kwargs(py::object obj, const py::kwargs& kwargs) {
  for (auto item : kwargs) {
    const std::string name = py::str(item.first);
    if (name.empty() || name[0] == '_' || !py::hasattr(obj, name.c_str()) ||
        py::isinstance<py::function>(py::getattr(obj, name.c_str()))) {
      std::string valid;
      for (py::handle a : py::module_::import("builtins").attr("dir")(obj)) {
        const std::string s = py::str(a);
        if (s[0] != '_' && !py::isinstance<py::function>(py::getattr(obj, a))) valid += (valid.empty() ? "" : ", ") + s;
      }
      throw py::type_error(std::string(py::str(py::type::of(obj).attr("__name__"))) + ": unknown option '" + name +
                           "' (valid: " + valid + ")");
    }
    py::setattr(obj, name.c_str(), item.second);
  }
}

std::string repr_from_fields(const py::handle& obj, const char* type_name, const std::vector<const char*>& fields) {
  std::string s = std::string(type_name) + "(";
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) s += ", ";
    s += std::string(fields[i]) + "=" + std::string(py::repr(obj.attr(fields[i])));
  }
  return s + ")";
}

namespace {

// InputError → slamkit.InputError(ValueError, slamkit.Error) with .file, .line, .field.
void register_exceptions(py::module_& m) {
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.doc() = "Base of the exceptions slamkit raises.";
  error.attr("__module__") = "slamkit";
  py::tuple input_bases = py::make_tuple(py::handle(PyExc_ValueError), error);
  static py::object input_error = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc("slamkit.InputError",
                                "Malformed, inconsistent or unusable input. A ValueError whose message reads "
                                "'FILE:LINE: field 'F': message'; attributes file, line (0: the whole input) "
                                "and field.",
                                input_bases.ptr(), nullptr));
  m.attr("InputError") = input_error;
  static py::object numerical_error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "slamkit.NumericalError", "A numerical failure (e.g. a matrix that is not positive definite).",
      py::make_tuple(py::handle(PyExc_ArithmeticError), error).ptr(), nullptr));
  m.attr("NumericalError") = numerical_error;

  py::register_exception_translator([](std::exception_ptr p) {
    if (!p) return;
    try {
      std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::object exc = input_error(py::str(e.what()));
      exc.attr("file") = e.file();
      exc.attr("line") = e.line();
      exc.attr("field") = e.field();
      PyErr_SetObject(input_error.ptr(), exc.ptr());
    } catch (const NumericalError& e) {
      PyErr_SetString(numerical_error.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
}

}  // namespace
}  // namespace slamkit::python

PYBIND11_MODULE(_slamkit, m) {
  namespace sp = slamkit::python;
  m.doc() =
      "slamkit: back-end SLAM toolkit (Lie groups, factor graphs, pose-graph optimization, trajectory "
      "evaluation) with NumPy in and out. See docs/python.md.";
  m.attr("__version__") = SLAMKIT_VERSION;
  sp::register_exceptions(m);
  m.def(
      "blas_runtime",
      [] {
        const slamkit::BlasRuntime r = slamkit::blas_runtime();
        pybind11::dict d;
        d["vendor"] = r.vendor, d["core"] = r.core, d["config"] = r.config;
        d["better_core"] = slamkit::better_openblas_core();
        return d;
      },
      "The BLAS CHOLMOD runs on: vendor, core (OpenBLAS kernel set), config, and better_core (non-empty "
      "when OpenBLAS runs generic kernels although this CPU could run that set).");
  sp::init_geometry(m);
  sp::init_core(m);
  sp::init_pose_graph(m);
  sp::init_solvers(m);
  sp::init_factors(m);
  sp::init_custom_factor(m);
  sp::init_sim(m);
  sp::init_io(m);
  sp::init_eval(m);
  sp::init_bundle_adjustment(m);
  sp::init_relaxers(m);
  sp::init_calibration(m);
  sp::init_filters(m);
  sp::init_vio(m);
  sp::init_frontend(m);
}
