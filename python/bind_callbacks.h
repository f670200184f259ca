// Python callables invoked from C++ code that runs with the GIL released (the optimizer's
// iteration callback, progress printing, Python factors on worker threads).
// Invariant: no Python reference count is touched without the GIL — callables are held by a
// shared_ptr whose deleter takes the GIL, so std::function copies made by the library are safe.
#pragma once

#include <memory>

#include "bind_common.h"
#include "slamkit/solvers/optimizer_options.h"

namespace slamkit::python {

/// A Python object shared with C++ code that may copy or drop it without holding the GIL.
std::shared_ptr<py::object> share_python_object(py::object obj);

/// Sets o.callback to call `user_callback(IterationSummary) -> bool|None` (None: continue)
/// and/or print the CLI's per-iteration progress lines to sys.stdout when verbose. An
/// exception raised by the callback stops the run; it is rethrown by optimize().
void install_python_callback(OptimizerOptions& o, const py::object& user_callback, bool verbose);

/// ValueError for option values the optimizer cannot work with (NaN or negative tolerances,
/// absurd thread counts).
void validate_optimizer_options(const OptimizerOptions& o);

/// Options from keyword arguments (every field of OptimizerOptions; enums as the CLI's strings).
OptimizerOptions optimizer_options_from_kwargs(const py::kwargs& kwargs);

}  // namespace slamkit::python
