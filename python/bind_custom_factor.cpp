// CustomFactor: a factor whose residual and Jacobians come from a Python function, like
// GTSAM's CustomFactor. The optimizer calls it from its (GIL-free) worker threads; each
// call takes the GIL, converts the parameter blocks to SE2/SE3/SO2/SO3 objects or NumPy
// vectors, calls error(values, jacobians) and copies the arrays it returns:
//   jacobians=False → r                    (residual_dim,)
//   jacobians=True  → (r, [J_1, ..., J_k])  J_k of shape (residual_dim, tangent_dim_k)
// Jacobians are w.r.t. the right perturbation x_k ⊞ δ (vectors: x + δ), as for built-in
// factors. A non-finite result rejects the step (as C++ factors do); a Python exception or
// a wrong shape aborts the optimization and is re-raised by optimize().
#include <sstream>

#include "bind_values.h"
#include "slamkit/core/factor.h"

namespace slamkit::python {
namespace {

class PythonFactor final : public Factor {
 public:
  PythonFactor(std::vector<Key> keys, std::vector<const Manifold*> manifolds, int residual_dim,
               std::shared_ptr<const NoiseModel> noise, std::shared_ptr<const RobustKernel> kernel, py::object fn)
      : Factor(std::move(keys), residual_dim, std::move(noise), std::move(kernel)),
        manifolds_(std::move(manifolds)),
        fn_(new py::object(std::move(fn))) {}
  ~PythonFactor() override {
    py::gil_scoped_acquire gil;  // the last reference may go away on a C++ thread
    delete fn_;
  }

  const Manifold& variable_manifold(std::size_t k) const override { return *manifolds_[k]; }
  const py::object& function() const { return *fn_; }

  bool evaluate(const double* const* params, double* residual, double* const* jacobians) const override {
    py::gil_scoped_acquire gil;
    const std::size_t n = manifolds_.size();
    bool want_J = false;
    if (jacobians)
      for (std::size_t k = 0; k < n; ++k) want_J = want_J || jacobians[k] != nullptr;
    py::list values(n);
    for (std::size_t k = 0; k < n; ++k) values[k] = params_to_object(*manifolds_[k], params[k]);
    const py::object out = (*fn_)(values, want_J);  // error_already_set propagates to optimize()

    py::object r = out;
    py::object Js;
    if (want_J) {
      if (!py::isinstance<py::tuple>(out) || py::len(out) != 2)
        fail("with jacobians=True the function must return (residual, [J_1, ...])");
      r = out.cast<py::tuple>()[0];
      Js = out.cast<py::tuple>()[1];
      if (py::len(Js) != n) fail("returned " + std::to_string(py::len(Js)) + " Jacobians for " + std::to_string(n) + " variables");
    } else if (py::isinstance<py::tuple>(out)) {
      r = out.cast<py::tuple>()[0];  // (r, J) returned anyway: use r
    }
    bool finite = copy_array(r, residual_dim(), 1, residual, "residual");
    if (want_J) {
      for (std::size_t k = 0; k < n; ++k) {
        if (!jacobians[k]) continue;
        finite = copy_array(Js[py::int_(k)], residual_dim(), manifolds_[k]->tangent_dim(), jacobians[k],
                            ("Jacobian " + std::to_string(k)).c_str()) &&
                 finite;
      }
    }
    return finite;
  }

  std::string describe() const {
    std::ostringstream os;
    os << "CustomFactor(keys [";
    for (std::size_t k = 0; k < keys().size(); ++k) os << (k ? ", " : "") << key_to_string(keys()[k]);
    os << "], residual_dim " << residual_dim() << ")";
    return os.str();
  }

 private:
  [[noreturn]] void fail(const std::string& message) const { throw py::value_error(describe() + ": " + message); }

  // Copies a rows × cols array into column-major dst; false if it holds a non-finite value.
  bool copy_array(const py::handle& obj, int rows, int cols, double* dst, const char* what) const {
    const auto a = py::array_t<double, py::array::forcecast>::ensure(obj);
    if (!a) fail(std::string(what) + " is not a float array");
    const bool ok_shape = cols == 1 ? (a.ndim() == 1 && a.shape(0) == rows) || (a.ndim() == 0 && rows == 1) ||
                                          (a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == 1)
                                    : a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == cols;
    if (!ok_shape) {
      std::ostringstream os;
      os << what << " has shape (";
      for (py::ssize_t d = 0; d < a.ndim(); ++d) os << (d ? ", " : "") << a.shape(d);
      os << "), expected (" << rows << (cols == 1 ? ",)" : ", " + std::to_string(cols) + ")");
      fail(os.str());
    }
    bool finite = true;
    if (a.ndim() == 2) {
      const auto u = a.unchecked<2>();
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) finite = std::isfinite(dst[j * rows + i] = u(i, j)) && finite;
    } else {
      const double* p = a.data();
      for (int i = 0; i < rows; ++i) finite = std::isfinite(dst[i] = p[i]) && finite;
    }
    return finite;
  }

  std::vector<const Manifold*> manifolds_;
  py::object* fn_;  // deleted under the GIL
};

}  // namespace

void init_custom_factor(py::module_& m) {
  py::class_<PythonFactor, Factor, std::shared_ptr<PythonFactor>>(
      m, "CustomFactor",
      "A factor defined by a Python function error(values, jacobians) (like GTSAM's CustomFactor). values is "
      "the list of the variables' current values (SE2/SE3/SO2/SO3 objects or NumPy vectors, in key order); "
      "it returns the residual (residual_dim,) or, when jacobians is True, (residual, [J_1, ..., J_k]) with "
      "J_k of shape (residual_dim, tangent_dim_k) w.r.t. the right perturbation x ⊞ delta. "
      "types lists each variable's type: slamkit.SE2, 'SE3', 'Vector3' or an int n (a length-n vector).")
      .def(py::init([](const std::vector<Key>& keys, const py::sequence& types, const std::shared_ptr<NoiseModel>& noise,
                       const py::object& error, int residual_dim, const std::shared_ptr<RobustKernel>& kernel) {
             if (keys.empty()) throw py::value_error("CustomFactor: needs at least one key");
             if (py::len(types) != keys.size())
               throw py::value_error("CustomFactor: " + std::to_string(py::len(types)) + " types for " +
                                     std::to_string(keys.size()) + " keys");
             if (!noise) throw py::value_error("CustomFactor: noise model is None");
             if (!PyCallable_Check(error.ptr())) throw py::type_error("CustomFactor: error must be callable");
             if (residual_dim <= 0) residual_dim = noise->dim();
             if (noise->dim() != residual_dim)
               throw py::value_error("CustomFactor: noise model has dimension " + std::to_string(noise->dim()) +
                                     ", residual_dim is " + std::to_string(residual_dim));
             std::vector<const Manifold*> manifolds;
             for (py::handle t : types) manifolds.push_back(&manifold_from_spec(t));
             return std::make_shared<PythonFactor>(keys, std::move(manifolds), residual_dim, noise, kernel, error);
           }),
           py::arg("keys"), py::arg("types"), py::arg("noise"), py::arg("error"), py::arg("residual_dim") = 0,
           py::arg("kernel") = nullptr,
           "residual_dim defaults to the noise model's dimension.")
      .def_property_readonly("error_function", &PythonFactor::function)
      .def_property_readonly("types",
                             [](const PythonFactor& f) {
                               std::vector<std::string> t;
                               for (std::size_t k = 0; k < f.keys().size(); ++k) t.push_back(f.variable_manifold(k).name());
                               return t;
                             })
      .def("__repr__", &PythonFactor::describe);
}

}  // namespace slamkit::python
