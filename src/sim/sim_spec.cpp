#include "sim_spec.h"

#include <array>
#include <charconv>
#include <cmath>
#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit::sim_detail {

SpecParts split_spec(const std::string& spec) {
  SpecParts parts;
  std::string rest = spec.substr(4), params;
  const auto q = rest.find('?');
  if (q != std::string::npos) params = rest.substr(q + 1), rest = rest.substr(0, q);
  parts.world = rest;
  std::istringstream ps(params);
  for (std::string kv; std::getline(ps, kv, '&');) {
    const auto eq = kv.find('=');
    parts.params.emplace_back(kv.substr(0, eq), eq == std::string::npos ? "" : kv.substr(eq + 1));
  }
  return parts;
}

long long spec_integer(const std::string& spec, const std::string& key, const std::string& value, long long lo,
                       long long hi) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (value.empty() || ec != std::errc() || end != value.data() + value.size())
    throw InputError(spec, 0, key, "not an integer: '" + value + "'");
  if (v < lo || v > hi)
    throw InputError(spec, 0, key, std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                                       std::to_string(hi) + "]");
  return v;
}

double spec_number(const std::string& spec, const std::string& key, const std::string& value, double lo, double hi) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (value.empty() || ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v))
    throw InputError(spec, 0, key, "not a number: '" + value + "'");
  if (!(v >= lo && v < hi))
    throw InputError(spec, 0, key, value + " is out of range [" + spec_text(lo) + ", " + spec_text(hi) + ")");
  return v + 0.0;  // no −0: it would print as "-0" and still read back, but as a distinct value
}

std::string spec_text(double v) {
  std::array<char, 32> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), res.ptr);
}

}  // namespace slamkit::sim_detail
