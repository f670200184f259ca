// Bindings of slamkit/geometry: SO2, SE2, SO3, SE3 (right perturbation X ⊞ δ = X · Exp(δ),
// tangent order translation first), Similarity3 and Umeyama alignment.
// Every Jacobian follows J_out_in = ∂ Log(out⁻¹ · out(in ⊞ δ)) / ∂δ and is returned when the
// call asks for it with jacobians=True.
#include <pybind11/operators.h>

#include <sstream>
#include <type_traits>

#include "bind_common.h"
#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"
#include "slamkit/geometry/umeyama.h"
#include "slamkit/core/manifold.h"

namespace slamkit::python {
namespace {

// Dimension of the points a group acts on.
template <class G>
constexpr int kPointDim = G::kDim == 1 || std::is_same_v<G, SE2> ? 2 : 3;

template <class G>
typename G::Tangent tangent_arg(const py::handle& v) {
  return to_vector(v, G::kDim, "tangent vector");
}

// Jacobians as 2-D arrays, also when they are 1×1 or d×1 (SO2).
template <class M>
Eigen::MatrixXd jac(const M& J) {
  return J;
}

// Members every Lie group shares (the math is in the C++ headers).
template <class G>
void bind_group_common(py::class_<G>& c) {
  using J = typename G::Jacobian;
  c.def_static("identity", &G::identity, "The identity element.")
      .def_static(
          "exp",
          [](const py::handle& tau, bool jacobians) -> py::object {
            J Jt;
            const G g = G::exp(tangent_arg<G>(tau), jacobians ? &Jt : nullptr);
            if (jacobians) return py::make_tuple(g, jac(Jt));
            return py::cast(g);
          },
          py::arg("tau"), py::arg("jacobians") = false,
          "Exp(tau); with jacobians=True returns (X, J) with J = right Jacobian Jr(tau).")
      .def(
          "log",
          [](const G& g, bool jacobians) -> py::object {
            J Jl;
            const typename G::Tangent t = g.log(jacobians ? &Jl : nullptr);
            if (jacobians) return py::make_tuple(t, jac(Jl));
            return py::cast(t);
          },
          py::arg("jacobians") = false, "Log(X) as a tangent vector; with jacobians=True returns (tau, Jr^-1(tau)).")
      .def(
          "compose",
          [](const G& a, const G& b, bool jacobians) -> py::object {
            J Ja, Jb;
            const G g = a.compose(b, jacobians ? &Ja : nullptr, jacobians ? &Jb : nullptr);
            if (jacobians) return py::make_tuple(g, jac(Ja), jac(Jb));
            return py::cast(g);
          },
          py::arg("other"), py::arg("jacobians") = false,
          "self * other; with jacobians=True returns (X, J_self, J_other).")
      .def(
          "inverse",
          [](const G& a, bool jacobians) -> py::object {
            J Ja;
            const G g = a.inverse(jacobians ? &Ja : nullptr);
            if (jacobians) return py::make_tuple(g, jac(Ja));
            return py::cast(g);
          },
          py::arg("jacobians") = false, "self^-1; with jacobians=True returns (X, J_self).")
      .def(
          "between",
          [](const G& a, const G& b, bool jacobians) -> py::object {
            J Ja, Jb;
            const G g = a.between(b, jacobians ? &Ja : nullptr, jacobians ? &Jb : nullptr);
            if (jacobians) return py::make_tuple(g, jac(Ja), jac(Jb));
            return py::cast(g);
          },
          py::arg("other"), py::arg("jacobians") = false,
          "self^-1 * other; with jacobians=True returns (X, J_self, J_other).")
      .def(
          "plus",
          [](const G& a, const py::handle& d, bool jacobians) -> py::object {
            J Ja, Jd;
            const G g = a.plus(tangent_arg<G>(d), jacobians ? &Ja : nullptr, jacobians ? &Jd : nullptr);
            if (jacobians) return py::make_tuple(g, jac(Ja), jac(Jd));
            return py::cast(g);
          },
          py::arg("delta"), py::arg("jacobians") = false,
          "self ⊞ delta = self * Exp(delta); with jacobians=True returns (X, J_self, J_delta).")
      .def(
          "minus",
          [](const G& a, const G& b, bool jacobians) -> py::object {
            J Ja, Jb;
            const typename G::Tangent t = a.minus(b, jacobians ? &Ja : nullptr, jacobians ? &Jb : nullptr);
            if (jacobians) return py::make_tuple(t, jac(Ja), jac(Jb));
            return py::cast(t);
          },
          py::arg("other"), py::arg("jacobians") = false,
          "self ⊟ other = Log(other^-1 * self); with jacobians=True returns (tau, J_self, J_other).")
      .def("adjoint", [](const G& g) { return jac(g.adjoint()); }, "Adjoint matrix Ad(X): X Exp(tau) = Exp(Ad tau) X.")
      .def("matrix", &G::matrix, "Homogeneous (or rotation) matrix.")
      .def("__mul__", [](const G& a, const G& b) { return a * b; }, py::is_operator())
      .def_static("right_jacobian", [](const py::handle& t) { return jac(G::right_jacobian(tangent_arg<G>(t))); },
                  py::arg("tau"), "Jr(tau).")
      .def_static("left_jacobian", [](const py::handle& t) { return jac(G::left_jacobian(tangent_arg<G>(t))); },
                  py::arg("tau"), "Jl(tau) = Jr(-tau).")
      .def_static("right_jacobian_inverse",
                  [](const py::handle& t) { return jac(G::right_jacobian_inverse(tangent_arg<G>(t))); }, py::arg("tau"),
                  "Jr(tau)^-1.")
      .def_static("left_jacobian_inverse",
                  [](const py::handle& t) { return jac(G::left_jacobian_inverse(tangent_arg<G>(t))); }, py::arg("tau"),
                  "Jl(tau)^-1.")
      .def_readonly_static("dim", &G::kDim, "Tangent dimension.")
      .def(py::pickle(
          [](const G& g) {
            Eigen::Matrix<double, ManifoldTraits<G>::kAmbient, 1> p;
            ManifoldTraits<G>::to_params(g, p.data());
            return py::make_tuple(p);
          },
          [](const py::tuple& t) {
            const Eigen::Matrix<double, ManifoldTraits<G>::kAmbient, 1> p =
                to_vector(t[0], ManifoldTraits<G>::kAmbient, "state");
            return ManifoldTraits<G>::from_params(p.data());
          }));
  // act on one point (returns a point, optionally with Jacobians) or on N points (N×d array).
  c.def(
      "act",
      [](const G& g, const py::handle& p, bool jacobians) -> py::object {
        py::array a = py::array::ensure(p);
        if (a && a.ndim() == 2) {
          if (jacobians) throw py::value_error("act: jacobians=True needs a single point");
          const RowMatrixXd pts = to_matrix(p, -1, kPointDim<G>, "points");
          RowMatrixXd out(pts.rows(), kPointDim<G>);
          using Vec = Eigen::Matrix<double, kPointDim<G>, 1>;
          for (Eigen::Index i = 0; i < pts.rows(); ++i) out.row(i) = g.act(Vec(pts.row(i).transpose())).transpose();
          return py::cast(out);
        }
        using Vec = Eigen::Matrix<double, kPointDim<G>, 1>;
        const Vec v = to_vector(p, kPointDim<G>, "point");
        if (!jacobians) return py::cast(Vec(g.act(v)));
        Eigen::Matrix<double, Vec::RowsAtCompileTime, G::kDim> Jg;
        Eigen::Matrix<double, Vec::RowsAtCompileTime, Vec::RowsAtCompileTime> Jp;
        const Vec out = g.act(v, &Jg, &Jp);
        return py::make_tuple(out, jac(Jg), jac(Jp));
      },
      py::arg("points"), py::arg("jacobians") = false,
      "Transforms one point (returns the point; with jacobians=True (p', J_self, J_point)) or an N×d array of "
      "points (returns N×d).");
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

Eigen::Quaterniond quaternion_xyzw(const py::handle& q) {
  const Eigen::Vector4d v = to_vector(q, 4, "quaternion [qx, qy, qz, qw]");
  if (v.norm() < 1e-12) throw py::value_error("quaternion [qx, qy, qz, qw]: zero norm");
  return Eigen::Quaterniond(v(3), v(0), v(1), v(2));
}

// A 3×3 matrix to be projected to the nearest rotation; a degenerate one (det <= 0) raises.
Eigen::Matrix3d rotation_matrix_arg(const py::handle& R) {
  const Eigen::Matrix3d M = to_matrix(R, 3, 3, "rotation matrix");
  if (!(M.determinant() > 1e-9)) throw py::value_error("rotation matrix: determinant is not positive");
  return M;
}

}  // namespace

void init_geometry(py::module_& m) {
  // ---- SO2 ----
  py::class_<SO2> so2(m, "SO2", "Planar rotation, stored as an angle wrapped to (-pi, pi]. Tangent: the angle.");
  so2.def(py::init<>())
      .def(py::init([](double angle) {
             require_finite(angle, "angle");
             return SO2(angle);
           }),
           py::arg("angle"))
      .def_static("from_matrix",
                  [](const py::handle& R) {
                    const Eigen::Matrix2d M = to_matrix(R, 2, 2, "matrix");
                    if (!(M.determinant() > 1e-9)) throw py::value_error("rotation matrix: determinant is not positive");
                    return SO2::from_matrix(M);
                  },
                  py::arg("matrix"), "From a 2×2 rotation matrix.")
      .def_property_readonly("angle", &SO2::angle)
      .def("__repr__", [](const SO2& r) { return "SO2(angle=" + fmt(r.angle()) + ")"; });
  bind_group_common(so2);

  // ---- SE2 ----
  py::class_<SE2> se2(m, "SE2", "Planar rigid motion (R, t), p -> R p + t. Tangent [rho_x, rho_y, theta].");
  se2.def(py::init<>())
      .def(py::init([](double x, double y, double theta) {
             require_finite(x, "x"), require_finite(y, "y"), require_finite(theta, "theta");
             return SE2(x, y, theta);
           }),
           py::arg("x"), py::arg("y"), py::arg("theta"))
      .def(py::init([](const SO2& R, const py::handle& t) { return SE2(R, to_vector(t, 2, "translation")); }),
           py::arg("rotation"), py::arg("translation"))
      .def_static(
          "from_matrix",
          [](const py::handle& T) {
            const RowMatrixXd M = to_matrix(T, 3, 3, "matrix");
            return SE2(SO2::from_matrix(M.topLeftCorner<2, 2>()), M.topRightCorner<2, 1>());
          },
          py::arg("matrix"), "From a 3×3 homogeneous matrix.")
      .def_static(
          "from_vector", [](const py::handle& v) {
            const Eigen::Vector3d x = to_vector(v, 3, "[x, y, theta]");
            return SE2(x(0), x(1), x(2));
          },
          py::arg("xytheta"), "From [x, y, theta].")
      .def("vector", [](const SE2& g) { return Eigen::Vector3d(g.x(), g.y(), g.theta()); }, "[x, y, theta].")
      .def_property_readonly("rotation", &SE2::rotation)
      .def_property_readonly("translation", [](const SE2& g) { return Eigen::Vector2d(g.translation()); })
      .def_property_readonly("x", &SE2::x)
      .def_property_readonly("y", &SE2::y)
      .def_property_readonly("theta", &SE2::theta)
      .def("__repr__",
           [](const SE2& g) { return "SE2(x=" + fmt(g.x()) + ", y=" + fmt(g.y()) + ", theta=" + fmt(g.theta()) + ")"; });
  bind_group_common(se2);

  // ---- SO3 ----
  py::class_<SO3> so3(m, "SO3", "3D rotation, stored as a unit quaternion. Tangent: the rotation vector.");
  so3.def(py::init<>())
      .def(py::init([](const py::handle& q) { return SO3(quaternion_xyzw(q)); }), py::arg("quaternion"),
           "From a quaternion [qx, qy, qz, qw] (normalized).")
      .def_static("from_matrix", [](const py::handle& R) { return SO3::from_matrix(rotation_matrix_arg(R)); },
                  py::arg("matrix"), "Nearest rotation to a 3×3 (nearly) orthonormal matrix.")
      .def_static("from_quaternion", [](const py::handle& q) { return SO3(quaternion_xyzw(q)); },
                  py::arg("quaternion"), "From [qx, qy, qz, qw].")
      .def_static(
          "from_rpy",
          [](double r, double p, double y) {
            require_finite(r, "roll"), require_finite(p, "pitch"), require_finite(y, "yaw");
            return SO3::from_rpy(r, p, y);
          },
          py::arg("roll"), py::arg("pitch"), py::arg("yaw"), "R = Rz(yaw) Ry(pitch) Rx(roll).")
      .def("to_rpy", &SO3::to_rpy, "[roll, pitch, yaw] of R = Rz(yaw) Ry(pitch) Rx(roll).")
      .def("quaternion", [](const SO3& r) { return Eigen::Vector4d(r.quaternion().coeffs()); }, "[qx, qy, qz, qw].")
      .def("__repr__", [](const SO3& r) {
        const Eigen::Vector4d q = r.quaternion().coeffs();
        return "SO3(quaternion=[" + fmt(q(0)) + ", " + fmt(q(1)) + ", " + fmt(q(2)) + ", " + fmt(q(3)) + "])";
      });
  bind_group_common(so3);

  // ---- SE3 ----
  py::class_<SE3> se3(m, "SE3", "Rigid motion (R, t), p -> R p + t. Tangent [rho; phi] (translation first).");
  se3.def(py::init<>())
      .def(py::init([](const SO3& R, const py::handle& t) { return SE3(R, to_vector(t, 3, "translation")); }),
           py::arg("rotation"), py::arg("translation"))
      .def(py::init([](const py::handle& q, const py::handle& t) {
             return SE3(quaternion_xyzw(q), to_vector(t, 3, "translation"));
           }),
           py::arg("quaternion"), py::arg("translation"), "From [qx, qy, qz, qw] and [tx, ty, tz].")
      .def_static(
          "from_matrix",
          [](const py::handle& T) {
            py::array a = py::array::ensure(T);
            const Eigen::Index rows = a && a.ndim() == 2 && a.shape(0) == 3 ? 3 : 4;
            const RowMatrixXd M = to_matrix(T, rows, 4, "matrix");
            rotation_matrix_arg(py::cast(Eigen::Matrix3d(M.topLeftCorner<3, 3>())));
            return SE3::from_matrix(M.topRows<3>());
          },
          py::arg("matrix"), "From a 4×4 or 3×4 [R | t] matrix (R projected to the nearest rotation).")
      .def_static(
          "from_vector",
          [](const py::handle& v) {
            const Eigen::Matrix<double, 7, 1> x = to_vector(v, 7, "[tx, ty, tz, qx, qy, qz, qw]");
            return SE3(quaternion_xyzw(py::cast(Eigen::Vector4d(x.tail<4>()))), x.head<3>());
          },
          py::arg("vector"), "From [tx, ty, tz, qx, qy, qz, qw] (the TUM / Values layout).")
      .def("vector",
           [](const SE3& g) {
             Eigen::Matrix<double, 7, 1> v;
             v << g.translation(), g.rotation().quaternion().coeffs();
             return v;
           },
           "[tx, ty, tz, qx, qy, qz, qw].")
      .def_property_readonly("rotation", &SE3::rotation)
      .def_property_readonly("translation", [](const SE3& g) { return Eigen::Vector3d(g.translation()); })
      .def("__repr__", [](const SE3& g) {
        const Eigen::Vector3d t = g.translation();
        const Eigen::Vector4d q = g.rotation().quaternion().coeffs();
        return "SE3(quaternion=[" + fmt(q(0)) + ", " + fmt(q(1)) + ", " + fmt(q(2)) + ", " + fmt(q(3)) +
               "], translation=[" + fmt(t(0)) + ", " + fmt(t(1)) + ", " + fmt(t(2)) + "])";
      });
  bind_group_common(se3);

  // ---- Similarity3 and Umeyama ----
  py::class_<Similarity3>(m, "Similarity3", "Similarity p -> s R p + t (a rigid motion when scale = 1).")
      .def(py::init<>())
      .def(py::init([](const py::handle& R, const py::handle& t, double s) {
             require_finite(s, "scale");
             Similarity3 S;
             S.R = rotation_matrix_arg(R);
             S.t = to_vector(t, 3, "translation");
             S.scale = s;
             return S;
           }),
           py::arg("rotation"), py::arg("translation"), py::arg("scale") = 1.0)
      .def_property(
          "rotation", [](const Similarity3& S) { return S.R; },
          [](Similarity3& S, const py::handle& R) { S.R = rotation_matrix_arg(R); }, "3×3 rotation matrix R.")
      .def_property(
          "translation", [](const Similarity3& S) { return S.t; },
          [](Similarity3& S, const py::handle& t) { S.t = to_vector(t, 3, "translation"); })
      .def_readwrite("scale", &Similarity3::scale)
      .def("matrix", &Similarity3::matrix, "[[s R, t], [0, 1]].")
      .def("inverse", &Similarity3::inverse, "p -> (1/s) R^T (p - t).")
      .def("rigid_part", &Similarity3::rigid_part, "(R, t) as an SE3.")
      .def(
          "apply",
          [](const Similarity3& S, const py::handle& p) -> py::object {
            py::array a = py::array::ensure(p);
            if (a && a.ndim() == 2) {
              RowMatrixXd pts = to_matrix(p, -1, 3, "points");
              for (Eigen::Index i = 0; i < pts.rows(); ++i)
                pts.row(i) = S.apply(Eigen::Vector3d(pts.row(i).transpose())).transpose();
              return py::cast(pts);
            }
            return py::cast(Eigen::Vector3d(S.apply(to_vector(p, 3, "point"))));
          },
          py::arg("points"), "s R p + t for one point or an N×3 array.")
      .def("__repr__", [](const Similarity3& S) {
        std::ostringstream os;
        os.precision(10);
        os << "Similarity3(scale=" << S.scale << ", translation=[" << S.t(0) << ", " << S.t(1) << ", " << S.t(2)
           << "])";
        return os.str();
      });

  m.def(
      "umeyama",
      [](const py::handle& src, const py::handle& dst, bool with_scale) {
        const RowMatrixXd a = to_matrix(src, -1, 3, "src"), b = to_matrix(dst, -1, 3, "dst");
        if (a.rows() != b.rows()) throw py::value_error("umeyama: src and dst have different numbers of points");
        return slamkit::umeyama(Eigen::Matrix3Xd(a.transpose()), Eigen::Matrix3Xd(b.transpose()), with_scale);
      },
      py::arg("src"), py::arg("dst"), py::arg("with_scale") = false,
      "Least-squares similarity (with_scale) or rigid motion taking the N×3 points src onto dst (Umeyama 1991).");
  m.def(
      "umeyama_yaw",
      [](const py::handle& src, const py::handle& dst) {
        const RowMatrixXd a = to_matrix(src, -1, 3, "src"), b = to_matrix(dst, -1, 3, "dst");
        if (a.rows() != b.rows()) throw py::value_error("umeyama_yaw: src and dst have different numbers of points");
        return slamkit::umeyama_yaw(Eigen::Matrix3Xd(a.transpose()), Eigen::Matrix3Xd(b.transpose()));
      },
      py::arg("src"), py::arg("dst"), "Rotation about z plus translation (4 DoF) taking src onto dst.");
}

}  // namespace slamkit::python
