// Type dispatch between Python objects and the typed variables of Values: SO2, SE2, SO3,
// SE3 objects and NumPy vectors of length 1..kMaxVectorDim. Shared by the core bindings and
// the Python-defined factor, which converts parameter blocks to the same objects.
#pragma once

#include <utility>

#include "bind_common.h"
#include "slamkit/core/manifold.h"
#include "slamkit/core/values.h"

namespace slamkit::python {

constexpr int kMaxVectorDim = 9;

/// Calls f(std::integral_constant<int, N>{}) for n = N in 1..kMaxVectorDim; ValueError otherwise.
template <class F>
decltype(auto) with_vector_dim(int n, F&& f) {
  switch (n) {
    case 1: return f(std::integral_constant<int, 1>{});
    case 2: return f(std::integral_constant<int, 2>{});
    case 3: return f(std::integral_constant<int, 3>{});
    case 4: return f(std::integral_constant<int, 4>{});
    case 5: return f(std::integral_constant<int, 5>{});
    case 6: return f(std::integral_constant<int, 6>{});
    case 7: return f(std::integral_constant<int, 7>{});
    case 8: return f(std::integral_constant<int, 8>{});
    case 9: return f(std::integral_constant<int, 9>{});
    default:
      throw py::value_error("vector variables have length 1.." + std::to_string(kMaxVectorDim) + ", got " +
                            std::to_string(n));
  }
}

/// The manifold a Python value lives on (SO2/SE2/SO3/SE3 objects, else a float vector).
const Manifold& manifold_of_value(const py::handle& value);
/// The manifold named by a type spec: slamkit.SE2 (the class), "SE2", "Vector3", or an int n (Vector n).
const Manifold& manifold_from_spec(const py::handle& spec);
/// A parameter block as a Python object of its manifold's type (vectors: NumPy arrays).
py::object params_to_object(const Manifold& m, const double* params);
/// Writes a Python value into a parameter block of manifold m; ValueError on a type mismatch.
void object_to_params(const Manifold& m, const py::handle& value, double* params);

}  // namespace slamkit::python
