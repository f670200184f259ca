// Parsing of "sim:WORLD?key=value&key=value" specs, shared by the generators' spec readers.
// Values are strict: the whole text is the number, within its range; errors are InputError
// naming the spec and the key.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace slamkit::sim_detail {

struct SpecParts {
  std::string world;                                        ///< text between "sim:" and '?'
  std::vector<std::pair<std::string, std::string>> params;  ///< in the order written
};

/// Splits a spec that starts with "sim:"; an empty item ("a=1&&b=2") is a parameter with an empty key.
SpecParts split_spec(const std::string& spec);

/// The whole of `value` as a decimal integer in [lo, hi].
long long spec_integer(const std::string& spec, const std::string& key, const std::string& value, long long lo,
                       long long hi);
/// The whole of `value` as a finite decimal number in [lo, hi).
double spec_number(const std::string& spec, const std::string& key, const std::string& value, double lo, double hi);
/// Shortest decimal text that spec_number reads back to exactly v.
std::string spec_text(double v);

}  // namespace slamkit::sim_detail
