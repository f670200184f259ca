// Small text helpers shared by the tests that inspect generated SVG/HTML/JSON text.
#pragma once

#include <cstddef>
#include <string>

namespace slamkit::testing {

/// Number of (possibly overlapping) occurrences of `what` in `s`.
inline std::size_t count_occurrences(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace slamkit::testing
