// The dynamic-group rule (see the header).
#include "slamkit/vio/dynamic_groups.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace slamkit {

void check_dynamic_group_options(const DynamicGroupOptions& options) {
  if (options.min_support < 0)
    throw std::invalid_argument("dynamic groups: min_support must be >= 0, got " + std::to_string(options.min_support));
  if (options.turned_min_support < 0 || options.turned_static_tests < 1 || options.turned_static_tests > 16)
    throw std::invalid_argument("dynamic groups: turned_min_support must be >= 0 and turned_static_tests in 1..16");
  if (!(std::isfinite(options.radius_factor) && options.radius_factor > 0.0))
    throw std::invalid_argument("dynamic groups: radius_factor must be finite and > 0");
}

int mark_isolated_flags(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                        const DynamicGroupOptions& options, double radius_px, std::vector<char>* isolated,
                        const std::vector<char>* turned) {
  if (uv.size() != flags.size() || (turned && turned->size() != flags.size()))
    throw std::invalid_argument("mark_isolated_flags: " + std::to_string(uv.size()) + " pixels but " +
                                std::to_string(flags.size()) + " flags" +
                                (turned ? " and " + std::to_string(turned->size()) + " turned marks" : std::string()));
  isolated->assign(flags.size(), 0);
  if (options.min_support <= 0) return 0;
  std::vector<std::size_t> flagged;
  for (std::size_t i = 0; i < uv.size(); ++i)
    if (flags[i] == FeatureMotion::kDynamic && uv[i].allFinite()) flagged.push_back(i);
  const double r2 = radius_px * radius_px;
  int marked = 0;
  const int turned_support = std::max(options.min_support, options.turned_min_support);
  for (const std::size_t i : flagged) {
    const int need = turned && (*turned)[i] ? turned_support : options.min_support;
    int support = 0;
    for (const std::size_t j : flagged)
      if (j != i && (uv[j] - uv[i]).squaredNorm() <= r2 && ++support >= need) break;
    if (support < need) (*isolated)[i] = 1, ++marked;
  }
  return marked;
}

}  // namespace slamkit
