// Manifolds that variables live on.
//
// ManifoldTraits<T> describes a C++ type as a manifold: its parameter block (ambient
// representation stored in Values) and its tangent space, with retraction x ⊞ δ. Every
// Lie group uses its right perturbation x ⊞ δ = x · Exp(δ); vectors use x + δ.
//   type            parameters (ambient)            tangent
//   SO2             [θ]                             1
//   SE2             [x, y, θ]                       3  [ρ; θ]
//   SO3             [qx, qy, qz, qw]                3
//   SE3             [tx, ty, tz, qx, qy, qz, qw]    6  [ρ; φ]
//   Eigen::Matrix<double, N, 1>   the vector        N
// Manifold is the type-erased form used by Values; one immutable instance per type.
#pragma once

#include <Eigen/Core>
#include <string>
#include <type_traits>

#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

template <class T>
struct ManifoldTraits;

template <>
struct ManifoldTraits<SO2> {
  static constexpr int kAmbient = 1, kTangent = 1;
  static const char* name() { return "SO2"; }
  static void to_params(const SO2& x, double* p) { p[0] = x.angle(); }
  static SO2 from_params(const double* p) { return SO2(p[0]); }
};

template <>
struct ManifoldTraits<SE2> {
  static constexpr int kAmbient = 3, kTangent = 3;
  static const char* name() { return "SE2"; }
  static void to_params(const SE2& x, double* p) { p[0] = x.x(), p[1] = x.y(), p[2] = x.theta(); }
  static SE2 from_params(const double* p) { return SE2(p[0], p[1], p[2]); }
};

template <>
struct ManifoldTraits<SO3> {
  static constexpr int kAmbient = 4, kTangent = 3;
  static const char* name() { return "SO3"; }
  static void to_params(const SO3& x, double* p) { Eigen::Map<Eigen::Vector4d> q(p); q = x.quaternion().coeffs(); }
  static SO3 from_params(const double* p) { return SO3(Eigen::Quaterniond(Eigen::Map<const Eigen::Vector4d>(p))); }
};

template <>
struct ManifoldTraits<SE3> {
  static constexpr int kAmbient = 7, kTangent = 6;
  static const char* name() { return "SE3"; }
  static void to_params(const SE3& x, double* p) {
    Eigen::Map<Eigen::Vector3d> t(p);
    Eigen::Map<Eigen::Vector4d> q(p + 3);
    t = x.translation();
    q = x.rotation().quaternion().coeffs();
  }
  static SE3 from_params(const double* p) {
    return SE3(Eigen::Quaterniond(Eigen::Map<const Eigen::Vector4d>(p + 3)), Eigen::Map<const Eigen::Vector3d>(p));
  }
};

template <int N>
struct ManifoldTraits<Eigen::Matrix<double, N, 1>> {
  static_assert(N > 0, "vector variables need a fixed size");
  using Vec = Eigen::Matrix<double, N, 1>;
  static constexpr int kAmbient = N, kTangent = N;
  static std::string name() { return "Vector" + std::to_string(N); }
  static void to_params(const Vec& x, double* p) { Eigen::Map<Vec> v(p); v = x; }
  static Vec from_params(const double* p) { return Eigen::Map<const Vec>(p); }
};

/// Retraction for typed values: x ⊞ δ.
template <class T, class Delta>
T retract(const T& x, const Delta& delta) {
  if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>) {
    return x + delta;
  } else {
    return x.plus(typename T::Tangent(delta));
  }
}

/// Type-erased manifold: what Values needs to store and update any variable.
class Manifold {
 public:
  virtual ~Manifold() = default;
  virtual int ambient_dim() const = 0;
  virtual int tangent_dim() const = 0;
  virtual std::string name() const = 0;
  /// out = x ⊞ delta on parameter blocks (out may alias x).
  virtual void plus(const double* x, const double* delta, double* out) const = 0;
};

template <class T>
class ManifoldOf final : public Manifold {
 public:
  using Traits = ManifoldTraits<T>;
  int ambient_dim() const override { return Traits::kAmbient; }
  int tangent_dim() const override { return Traits::kTangent; }
  std::string name() const override { return Traits::name(); }
  void plus(const double* x, const double* delta, double* out) const override {
    const T y = retract(Traits::from_params(x), Eigen::Map<const Eigen::Matrix<double, Traits::kTangent, 1>>(delta));
    Traits::to_params(y, out);
  }
  /// The one immutable instance for T.
  static const ManifoldOf& instance() {
    static const ManifoldOf m;
    return m;
  }
};

}  // namespace slamkit
