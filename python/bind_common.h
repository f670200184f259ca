// Shared helpers of the slamkit Python bindings: argument checks that raise instead of
// crashing, NumPy conversions, and the per-module init functions called by module.cpp.
//
// Conventions of the whole module: NumPy float64 arrays in and out; quaternions as
// [qx, qy, qz, qw] (Eigen's and TUM's order, the order of Values' parameter blocks); a
// wrong shape or a non-finite number raises ValueError (never a crash), slamkit's
// InputError becomes slamkit.InputError (a ValueError naming file, line and field).
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace slamkit::python {

namespace py = pybind11;

/// Row-major dynamic matrix: the layout NumPy arrays have by default.
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Raises ValueError("<what>: not finite") unless every entry of m is finite.
template <class M>
void require_finite(const M& m, const char* what) {
  if (!m.allFinite()) throw py::value_error(std::string(what) + ": contains NaN or infinity");
}
inline void require_finite(double v, const char* what) {
  if (!std::isfinite(v)) throw py::value_error(std::string(what) + ": not finite");
}

/// A float64 array as an Eigen matrix of exactly rows × cols (−1: any); raises ValueError
/// naming `what` on a wrong shape or a non-finite entry. 1-D arrays count as column vectors.
RowMatrixXd to_matrix(const py::handle& obj, Eigen::Index rows, Eigen::Index cols, const char* what,
                      bool finite = true);
/// A 1-D (or n×1) float64 array of length n (−1: any).
Eigen::VectorXd to_vector(const py::handle& obj, Eigen::Index n, const char* what, bool finite = true);
/// An N×cols array (a single row of length cols is taken as N = 1 when allow_single).
RowMatrixXd to_rows(const py::handle& obj, Eigen::Index cols, const char* what, bool allow_single = true);

/// A NumPy copy of a std::vector.
template <class T>
py::array_t<T> to_array(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}
/// N×3 array from a list of 3-vectors.
py::array_t<double> to_array(const std::vector<Eigen::Vector3d>& v);

/// Sets every attribute named in kwargs on obj (plain option structs built with keywords);
/// unknown names raise TypeError listing the valid ones.
void set_from_kwargs(py::object obj, const py::kwargs& kwargs);
/// A readable `Name(field=value, ...)` repr from the listed attributes.
std::string repr_from_fields(const py::handle& obj, const char* type_name, const std::vector<const char*>& fields);

void init_geometry(py::module_& m);
void init_core(py::module_& m);
void init_pose_graph(py::module_& m);
void init_solvers(py::module_& m);
void init_factors(py::module_& m);
void init_custom_factor(py::module_& m);
void init_sim(py::module_& m);
void init_io(py::module_& m);
void init_eval(py::module_& m);
void init_bundle_adjustment(py::module_& m);
void init_relaxers(py::module_& m);
void init_calibration(py::module_& m);
void init_filters(py::module_& m);
void init_vio(py::module_& m);
void init_frontend(py::module_& m);

}  // namespace slamkit::python
