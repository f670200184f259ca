// printf into a std::string, for the progress lines and summaries of the solvers (the
// manifold solvers' Summary and the relaxers' RelaxerSummary). Internal to the solvers module.
#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

namespace slamkit::detail {

/// The printf-formatted string, whatever its length (sized by a first vsnprintf).
inline std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string format(const char* fmt, ...) {
  va_list args, copy;
  va_start(args, fmt);
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string out(n > 0 ? static_cast<std::size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(out.data(), out.size() + 1, fmt, args);
  va_end(args);
  return out;
}

}  // namespace slamkit::detail
