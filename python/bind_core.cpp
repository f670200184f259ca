// Bindings of slamkit/core: keys, Values, noise models, robust kernels, the Factor base,
// FactorGraph, the numeric Jacobian check and information-matrix health.
#include <sstream>

#include "bind_values.h"
#include "slamkit/core/factor_graph.h"
#include "slamkit/core/information.h"
#include "slamkit/core/jacobian_check.h"
#include "slamkit/core/key.h"
#include "slamkit/core/noise_model.h"
#include "slamkit/core/robust_kernel.h"

namespace slamkit::python {

const Manifold& manifold_of_value(const py::handle& value) {
  if (py::isinstance<SE2>(value)) return ManifoldOf<SE2>::instance();
  if (py::isinstance<SE3>(value)) return ManifoldOf<SE3>::instance();
  if (py::isinstance<SO2>(value)) return ManifoldOf<SO2>::instance();
  if (py::isinstance<SO3>(value)) return ManifoldOf<SO3>::instance();
  const Eigen::VectorXd v = to_vector(value, -1, "value", false);
  return with_vector_dim(static_cast<int>(v.size()), [](auto n) -> const Manifold& {
    return ManifoldOf<Eigen::Matrix<double, decltype(n)::value, 1>>::instance();
  });
}

const Manifold& manifold_from_spec(const py::handle& spec) {
  std::string name;
  if (py::isinstance<py::int_>(spec)) {
    name = "Vector" + std::to_string(spec.cast<int>());
  } else if (py::isinstance<py::str>(spec)) {
    name = spec.cast<std::string>();
  } else if (py::hasattr(spec, "__name__")) {
    name = py::str(spec.attr("__name__"));
  } else {
    throw py::value_error("variable type: expected slamkit.SE2/SE3/SO2/SO3, 'VectorN' or an int N");
  }
  if (name == "SE2") return ManifoldOf<SE2>::instance();
  if (name == "SE3") return ManifoldOf<SE3>::instance();
  if (name == "SO2") return ManifoldOf<SO2>::instance();
  if (name == "SO3") return ManifoldOf<SO3>::instance();
  if (name.rfind("Vector", 0) == 0 && name.size() > 6) {
    int n = 0;
    try {
      n = std::stoi(name.substr(6));
    } catch (const std::exception&) {
      throw py::value_error("variable type '" + name + "': not VectorN");
    }
    return with_vector_dim(n, [](auto k) -> const Manifold& {
      return ManifoldOf<Eigen::Matrix<double, decltype(k)::value, 1>>::instance();
    });
  }
  throw py::value_error("variable type '" + name + "': expected SE2, SE3, SO2, SO3 or VectorN");
}

namespace {

template <class T>
bool is(const Manifold& m) {
  return &m == &ManifoldOf<T>::instance();
}

template <class T>
void insert_typed(Values& v, Key key, const py::handle& value) {
  v.insert(key, value.cast<T>());
}

void insert_value(Values& values, Key key, const py::handle& value) {
  if (py::isinstance<SE2>(value)) return insert_typed<SE2>(values, key, value);
  if (py::isinstance<SE3>(value)) return insert_typed<SE3>(values, key, value);
  if (py::isinstance<SO2>(value)) return insert_typed<SO2>(values, key, value);
  if (py::isinstance<SO3>(value)) return insert_typed<SO3>(values, key, value);
  const Eigen::VectorXd x = to_vector(value, -1, "value");
  with_vector_dim(static_cast<int>(x.size()), [&](auto n) {
    using Vec = Eigen::Matrix<double, decltype(n)::value, 1>;
    values.insert(key, Vec(x));
  });
}

}  // namespace

py::object params_to_object(const Manifold& m, const double* p) {
  if (is<SE2>(m)) return py::cast(ManifoldTraits<SE2>::from_params(p));
  if (is<SE3>(m)) return py::cast(ManifoldTraits<SE3>::from_params(p));
  if (is<SO2>(m)) return py::cast(ManifoldTraits<SO2>::from_params(p));
  if (is<SO3>(m)) return py::cast(ManifoldTraits<SO3>::from_params(p));
  py::array_t<double> a(m.ambient_dim());
  std::copy(p, p + m.ambient_dim(), a.mutable_data());
  return std::move(a);
}

void object_to_params(const Manifold& m, const py::handle& value, double* p) {
  const Manifold& given = manifold_of_value(value);
  if (&given != &m) throw py::value_error("value is a " + given.name() + ", the variable a " + m.name());
  if (is<SE2>(m)) return ManifoldTraits<SE2>::to_params(value.cast<SE2>(), p);
  if (is<SE3>(m)) return ManifoldTraits<SE3>::to_params(value.cast<SE3>(), p);
  if (is<SO2>(m)) return ManifoldTraits<SO2>::to_params(value.cast<SO2>(), p);
  if (is<SO3>(m)) return ManifoldTraits<SO3>::to_params(value.cast<SO3>(), p);
  const Eigen::VectorXd x = to_vector(value, m.ambient_dim(), "value");
  std::copy(x.data(), x.data() + x.size(), p);
}

namespace {

// Parameter blocks of a factor's variables in `values`, checked against the factor's manifolds.
std::vector<const double*> gather_params(const Factor& f, const Values& values) {
  std::vector<const double*> params;
  for (std::size_t k = 0; k < f.keys().size(); ++k) {
    const std::size_t i = values.index_of(f.keys()[k]);
    if (&values.manifold(i) != &f.variable_manifold(k))
      throw InputError("", 0, "key",
                       "variable " + key_to_string(f.keys()[k]) + " is a " + values.manifold(i).name() +
                           ", the factor expects a " + f.variable_manifold(k).name());
    params.push_back(values.params(i));
  }
  return params;
}

// (residual, [J_k]) of a factor at values; whitened = noise model and kernel applied.
py::tuple factor_eval(const Factor& f, const Values& values, bool whitened) {
  const std::vector<const double*> params = gather_params(f, values);
  const int R = f.residual_dim();
  Eigen::VectorXd r(R);
  std::vector<Eigen::MatrixXd> J;  // column-major R × d_k, as Factor::evaluate writes them
  std::vector<double*> jac;
  for (std::size_t k = 0; k < params.size(); ++k) J.emplace_back(R, f.variable_manifold(k).tangent_dim());
  for (auto& j : J) jac.push_back(j.data());
  double cost = 0.0;
  bool ok = true;
  {
    py::gil_scoped_release release;  // a Python factor re-acquires it
    if (whitened)
      cost = f.linearize(params.data(), r.data(), jac.data());
    else
      ok = f.evaluate(params.data(), r.data(), jac.data());
  }
  py::list js;
  for (const auto& j : J) js.append(py::cast(j));
  if (whitened) return py::make_tuple(cost, r, js);
  if (!ok) throw NumericalError("factor evaluation is not finite");
  return py::make_tuple(r, js);
}

std::shared_ptr<NoiseModel> mutable_ptr(std::shared_ptr<const NoiseModel> p) {
  return std::const_pointer_cast<NoiseModel>(std::move(p));
}

}  // namespace

void init_core(py::module_& m) {
  // ---- keys ----
  m.def(
      "symbol",
      [](const std::string& c, std::uint64_t index) {
        if (c.size() != 1) throw py::value_error("symbol: expected a single character");
        if (index > kSymbolIndexMask) throw py::value_error("symbol: index does not fit in 56 bits");
        return symbol(c[0], index);
      },
      py::arg("char"), py::arg("index"), "GTSAM-style key: the character in the top 8 bits, the index below.");
  m.def("symbol_char", [](Key k) { return std::string(1, symbol_char(k)); }, py::arg("key"), "The character of a symbol key.");
  m.def("symbol_index", &symbol_index, py::arg("key"), "The index of a symbol key.");
  m.def("key_to_string", &key_to_string, py::arg("key"), "'x3' for symbol keys, the plain number otherwise.");

  // ---- Values ----
  py::class_<Values>(m, "Values",
                     "The variables of a problem: SE2, SE3, SO2, SO3 objects or float vectors (length 1..9), "
                     "each under an integer key; fixed variables are not optimized.")
      .def(py::init<>())
      .def("insert", &insert_value, py::arg("key"), py::arg("value"),
           "Adds a variable; InputError if the key exists. Vectors are given as arrays.")
      .def(
          "at",
          [](const Values& v, Key key) {
            const std::size_t i = v.index_of(key);
            return params_to_object(v.manifold(i), v.params(i));
          },
          py::arg("key"), "The variable's value (an SE2/SE3/SO2/SO3 object or a NumPy vector).")
      .def("__getitem__",
           [](const Values& v, Key key) {
             const std::size_t i = v.index_of(key);
             return params_to_object(v.manifold(i), v.params(i));
           })
      .def(
          "update",
          [](Values& v, Key key, const py::handle& value) {
            const std::size_t i = v.index_of(key);
            object_to_params(v.manifold(i), value, v.params(i));
          },
          py::arg("key"), py::arg("value"), "Replaces a variable's value (same type).")
      .def("exists", &Values::exists, py::arg("key"), "True if a variable has this key.")
      .def("__contains__", &Values::exists)
      .def("__len__", &Values::size)
      .def("size", &Values::size, "Number of variables.")
      .def("set_fixed", &Values::set_fixed, py::arg("key"), py::arg("fixed") = true,
           "Holds a variable fixed (gauge, known calibration): the optimizer leaves it alone.")
      .def("is_fixed", &Values::is_fixed, py::arg("key"), "True if the variable is held fixed.")
      .def("num_fixed", &Values::num_fixed, "Number of fixed variables.")
      .def(
          "keys",
          [](const Values& v) {
            py::array_t<std::uint64_t> a(static_cast<py::ssize_t>(v.size()));
            for (std::size_t i = 0; i < v.size(); ++i) a.mutable_data()[i] = v.key(i);
            return a;
          },
          "Keys in insertion order (uint64 array).")
      .def(
          "type_name", [](const Values& v, Key key) { return v.manifold(v.index_of(key)).name(); }, py::arg("key"),
          "'SE2', 'SE3', 'SO2', 'SO3' or 'VectorN'.")
      .def(
          "parameters",
          [](const Values& v) { return to_array(v.parameter_data()); },
          "All parameter blocks in insertion order, concatenated (a copy: the storage moves on insert). "
          "SE2 [x, y, theta], SE3 [t, qx, qy, qz, qw], SO2 [theta], SO3 [qx, qy, qz, qw], vectors as is.")
      .def(
          "se2_array",
          [](const Values& v, const std::vector<Key>& keys) {
            RowMatrixXd out(keys.size(), 3);
            for (std::size_t k = 0; k < keys.size(); ++k) {
              const SE2 x = v.at<SE2>(keys[k]);
              out.row(k) << x.x(), x.y(), x.theta();
            }
            return out;
          },
          py::arg("keys"), "N×3 [x, y, theta] of the SE2 variables at keys.")
      .def(
          "se3_array",
          [](const Values& v, const std::vector<Key>& keys) {
            RowMatrixXd out(keys.size(), 7);
            for (std::size_t k = 0; k < keys.size(); ++k)
              ManifoldTraits<SE3>::to_params(v.at<SE3>(keys[k]), out.row(k).data());
            return out;
          },
          py::arg("keys"), "N×7 [tx, ty, tz, qx, qy, qz, qw] of the SE3 variables at keys.")
      .def("copy", [](const Values& v) { return Values(v); }, "An independent copy.")
      .def("__copy__", [](const Values& v) { return Values(v); })
      .def("__deepcopy__", [](const Values& v, py::dict) { return Values(v); })
      .def("__repr__", [](const Values& v) {
        return "Values(" + std::to_string(v.size()) + " variables, " + std::to_string(v.num_fixed()) + " fixed)";
      });

  // ---- noise models ----
  py::class_<NoiseModel, std::shared_ptr<NoiseModel>> noise(
      m, "NoiseModel",
      "Gaussian noise as a square-root information R (R^T R = Omega); residuals are whitened to R r.");
  py::enum_<NoiseModel::Kind>(noise, "Kind")
      .value("UNIT", NoiseModel::Kind::kUnit)
      .value("DIAGONAL", NoiseModel::Kind::kDiagonal)
      .value("DENSE", NoiseModel::Kind::kDense);
  noise
      .def_static(
          "unit",
          [](int dim) {
            if (dim <= 0) throw py::value_error("dim must be positive");
            return mutable_ptr(NoiseModel::unit(dim));
          },
          py::arg("dim"))
      .def_static(
          "isotropic",
          [](int dim, double sigma) {
            if (dim <= 0) throw py::value_error("dim must be positive");
            if (!(sigma > 0.0) || !std::isfinite(sigma)) throw py::value_error("sigma must be positive and finite");
            return mutable_ptr(NoiseModel::isotropic(dim, sigma));
          },
          py::arg("dim"), py::arg("sigma"))
      .def_static(
          "diagonal",
          [](const py::handle& sigmas) {
            const Eigen::VectorXd s = to_vector(sigmas, -1, "sigmas");
            if (s.size() == 0 || (s.array() <= 0.0).any()) throw py::value_error("sigmas must be positive");
            return mutable_ptr(NoiseModel::diagonal(s));
          },
          py::arg("sigmas"), "Independent noise with standard deviations sigmas.")
      .def_static(
          "information",
          [](const py::handle& omega) {
            const Eigen::MatrixXd O = to_matrix(omega, -1, -1, "information");
            if (O.rows() != O.cols() || O.rows() == 0) throw py::value_error("information: expected a square matrix");
            return mutable_ptr(NoiseModel::information(O));
          },
          py::arg("omega"), "From an information matrix (symmetric positive definite, else NumericalError).")
      .def_static(
          "covariance",
          [](const py::handle& sigma) {
            const Eigen::MatrixXd S = to_matrix(sigma, -1, -1, "covariance");
            if (S.rows() != S.cols() || S.rows() == 0) throw py::value_error("covariance: expected a square matrix");
            return mutable_ptr(NoiseModel::covariance(S));
          },
          py::arg("sigma"), "From a covariance matrix (symmetric positive definite).")
      .def_property_readonly("kind", &NoiseModel::kind)
      .def_property_readonly("dim", &NoiseModel::dim)
      .def("sqrt_information", &NoiseModel::sqrt_information, "R (upper triangular) with R^T R = Omega.")
      .def("information_matrix", &NoiseModel::information_matrix, "Omega = Sigma^-1.")
      .def(
          "whiten",
          [](const NoiseModel& n, const py::handle& r) {
            Eigen::VectorXd v = to_vector(r, n.dim(), "residual");
            n.whiten(v.data());
            return v;
          },
          py::arg("residual"), "R r.")
      .def("__repr__", [](const NoiseModel& n) {
        const char* k = n.kind() == NoiseModel::Kind::kUnit ? "unit" : n.kind() == NoiseModel::Kind::kDiagonal ? "diagonal" : "dense";
        return std::string("NoiseModel(") + k + ", dim=" + std::to_string(n.dim()) + ")";
      });

  // ---- robust kernels ----
  py::class_<RobustKernel, std::shared_ptr<RobustKernel>>(
      m, "RobustKernel", "rho(s) of the squared whitened residual s; delta is the inlier scale.")
      .def_property_readonly("name", &RobustKernel::name)
      .def_property_readonly("delta", &RobustKernel::delta)
      .def(
          "evaluate",
          [](const RobustKernel& k, double s) {
            double rho[3];
            k.evaluate(s, rho);
            return py::make_tuple(rho[0], rho[1], rho[2]);
          },
          py::arg("s"), "(rho(s), rho'(s), rho''(s)).")
      .def("__repr__", [](const RobustKernel& k) {
        std::ostringstream os;
        os << "RobustKernel('" << k.name() << "', delta=" << k.delta() << ")";
        return os.str();
      });
  auto kernel_init = [](double delta) {
    if (!(delta > 0.0) || !std::isfinite(delta)) throw py::value_error("delta must be positive and finite");
    return delta;
  };
  py::class_<HuberKernel, RobustKernel, std::shared_ptr<HuberKernel>>(m, "HuberKernel", "s <= d^2: s, else 2 d sqrt(s) - d^2.")
      .def(py::init([=](double d) { return std::make_shared<HuberKernel>(kernel_init(d)); }), py::arg("delta"));
  py::class_<CauchyKernel, RobustKernel, std::shared_ptr<CauchyKernel>>(m, "CauchyKernel", "d^2 ln(1 + s / d^2).")
      .def(py::init([=](double d) { return std::make_shared<CauchyKernel>(kernel_init(d)); }), py::arg("delta"));
  py::class_<TukeyKernel, RobustKernel, std::shared_ptr<TukeyKernel>>(m, "TukeyKernel", "s <= d^2: d^2/3 (1 - (1 - s/d^2)^3), else d^2/3.")
      .def(py::init([=](double d) { return std::make_shared<TukeyKernel>(kernel_init(d)); }), py::arg("delta"));
  py::class_<GemanMcClureKernel, RobustKernel, std::shared_ptr<GemanMcClureKernel>>(m, "GemanMcClureKernel", "d^2 s / (d^2 + s).")
      .def(py::init([=](double d) { return std::make_shared<GemanMcClureKernel>(kernel_init(d)); }),
           py::arg("delta"));
  py::class_<DcsKernel, RobustKernel, std::shared_ptr<DcsKernel>>(m, "DcsKernel",
                                                                 "Dynamic covariance scaling (Agarwal et al. 2013).")
      .def(py::init([=](double d) { return std::make_shared<DcsKernel>(kernel_init(d)); }), py::arg("delta"));
  m.def(
      "make_robust_kernel",
      [](const std::string& name, double delta) {
        return std::const_pointer_cast<RobustKernel>(make_robust_kernel(name, delta));
      },
      py::arg("name"), py::arg("delta"), "'huber', 'cauchy', 'tukey', 'geman-mcclure' (or 'gm'), 'dcs'.");
  m.def(
      "parse_robust_kernel",
      [](const std::string& spec) { return std::const_pointer_cast<RobustKernel>(parse_robust_kernel(spec)); },
      py::arg("spec"), "From 'KERNEL:delta', e.g. 'cauchy:1' (the CLI's --robust).");

  // ---- factors and the graph ----
  py::class_<Factor, std::shared_ptr<Factor>>(
      m, "Factor",
      "One term rho(||R r(x)||^2) of the cost. Jacobians are w.r.t. tangent perturbations x ⊞ delta.")
      .def_property_readonly("keys", &Factor::keys)
      .def_property_readonly("residual_dim", &Factor::residual_dim)
      .def_property_readonly(
          "noise_model",
          // A copy (noise models are small and immutable): it may be given to other factors
          // and outlive this one.
          [](const Factor& f) { return f.noise_model()->clone(); },
          "The factor's noise model (a copy).")
      .def_property_readonly(
          "robust_kernel",
          [](const Factor& f) -> py::object {
            if (!f.robust_kernel()) return py::none();
            return py::cast(f.robust_kernel()->name() + ":" + std::to_string(f.robust_kernel()->delta()));
          },
          "'name:delta' of the kernel, or None.")
      .def(
          "error", [](const Factor& f, const Values& v) { return factor_eval(f, v, false); }, py::arg("values"),
          "Raw residual and Jacobians at values: (r, [J_1, ...]).")
      .def(
          "linearize", [](const Factor& f, const Values& v) { return factor_eval(f, v, true); }, py::arg("values"),
          "Whitened and robustified (cost, r, [J_1, ...]) as the optimizer uses them.")
      .def(
          "cost", [](const Factor& f, const Values& v) { return py::cast<double>(factor_eval(f, v, true)[0]); },
          py::arg("values"), "rho(||R r||^2) at values.");

  py::class_<FactorGraph>(m, "FactorGraph", "The factors of a problem; cost = sum of rho_f(||R_f r_f(x)||^2).")
      .def(py::init<>())
      .def(
          "add",
          [](FactorGraph& g, const std::shared_ptr<Factor>& f) {
            if (!f) throw py::value_error("add: factor is None");
            g.add(f);
          },
          py::arg("factor"), "Adds a factor (built-in or CustomFactor).")
      .def("__len__", &FactorGraph::size)
      .def("size", &FactorGraph::size, "Number of factors.")
      .def("__getitem__",
           [](const FactorGraph& g, std::ptrdiff_t i) {
             const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(g.size());
             if (i < 0) i += n;
             if (i < 0 || i >= n) throw py::index_error("factor index out of range");
             return std::const_pointer_cast<Factor>(g.factor(static_cast<std::size_t>(i)));
           })
      .def(
          "cost",
          [](const FactorGraph& g, const Values& v) {
            py::gil_scoped_release release;
            return g.cost(v);
          },
          py::arg("values"), "Total cost (g2o's chi2 without kernels).")
      .def("check_against", &FactorGraph::check_against, py::arg("values"),
           "InputError unless every key exists with the type its factor expects.")
      .def("__repr__", [](const FactorGraph& g) { return "FactorGraph(" + std::to_string(g.size()) + " factors)"; });

  py::class_<JacobianCheckResult>(m, "JacobianCheckResult", "Outcome of check_jacobians: ok, and where the worst entry is.")
      .def_readonly("ok", &JacobianCheckResult::ok)
      .def_readonly("worst_error", &JacobianCheckResult::worst_error)
      .def_readonly("factor", &JacobianCheckResult::factor)
      .def_readonly("variable", &JacobianCheckResult::variable)
      .def_readonly("row", &JacobianCheckResult::row)
      .def_readonly("col", &JacobianCheckResult::col)
      .def_readonly("analytic", &JacobianCheckResult::analytic)
      .def_readonly("numeric", &JacobianCheckResult::numeric)
      .def_readonly("factors_checked", &JacobianCheckResult::factors_checked)
      .def("message", &JacobianCheckResult::message, "Human-readable summary.")
      .def("__bool__", [](const JacobianCheckResult& r) { return r.ok; })
      .def("__repr__", [](const JacobianCheckResult& r) { return r.message(); });
  m.def(
      "check_jacobians",
      [](const FactorGraph& g, const Values& v, double tolerance, double step) {
        py::gil_scoped_release release;
        return check_jacobians(g, v, tolerance, step);
      },
      py::arg("graph"), py::arg("values"), py::arg("tolerance") = 1e-6, py::arg("step") = 1e-6,
      "Analytic Jacobians of every factor against central differences on the tangent space.");

  // ---- information-matrix health ----
  py::enum_<InformationStatus>(m, "InformationStatus")
      .value("POSITIVE_DEFINITE", InformationStatus::kPositiveDefinite)
      .value("SINGULAR", InformationStatus::kSingular)
      .value("INDEFINITE", InformationStatus::kIndefinite)
      .value("NOT_SYMMETRIC", InformationStatus::kNotSymmetric)
      .value("NOT_FINITE", InformationStatus::kNotFinite);
  py::class_<InformationCheck>(m, "InformationCheck", "Classification of one information matrix with its extreme eigenvalues.")
      .def_readonly("status", &InformationCheck::status)
      .def_readonly("min_eigenvalue", &InformationCheck::min_eigenvalue)
      .def_readonly("max_eigenvalue", &InformationCheck::max_eigenvalue);
  m.def(
      "check_information",
      [](const py::handle& omega) {
        const Eigen::MatrixXd O = to_matrix(omega, -1, -1, "information", false);
        if (O.rows() != O.cols()) throw py::value_error("information: expected a square matrix");
        return check_information(O);
      },
      py::arg("omega"), "Classifies an information matrix (PD / singular / indefinite / ...).");
  m.def(
      "project_to_psd",
      [](const py::handle& omega, double floor) {
        const Eigen::MatrixXd O = to_matrix(omega, -1, -1, "information");
        if (O.rows() != O.cols()) throw py::value_error("information: expected a square matrix");
        return project_to_psd(O, floor);
      },
      py::arg("omega"), py::arg("relative_floor") = 1e-9,
      "Nearest symmetric matrix with eigenvalues >= relative_floor * max eigenvalue.");
}

}  // namespace slamkit::python
