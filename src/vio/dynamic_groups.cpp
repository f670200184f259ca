// The dynamic-group rule (see the header).
#include "slamkit/vio/dynamic_groups.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace slamkit {

void check_dynamic_group_options(const DynamicGroupOptions& options) {
  if (options.min_support < 0)
    throw std::invalid_argument("dynamic groups: min_support must be >= 0, got " + std::to_string(options.min_support));
  if (!(std::isfinite(options.radius_factor) && options.radius_factor > 0.0))
    throw std::invalid_argument("dynamic groups: radius_factor must be finite and > 0");
}

int mark_isolated_flags(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                        const DynamicGroupOptions& options, double radius_px, std::vector<char>* isolated) {
  if (uv.size() != flags.size())
    throw std::invalid_argument("mark_isolated_flags: " + std::to_string(uv.size()) + " pixels but " +
                                std::to_string(flags.size()) + " flags");
  isolated->assign(flags.size(), 0);
  if (options.min_support <= 0) return 0;
  std::vector<std::size_t> flagged;
  for (std::size_t i = 0; i < uv.size(); ++i)
    if (flags[i] == FeatureMotion::kDynamic && uv[i].allFinite()) flagged.push_back(i);
  const double r2 = radius_px * radius_px;
  int marked = 0;
  for (const std::size_t i : flagged) {
    int support = 0;
    for (const std::size_t j : flagged)
      if (j != i && (uv[j] - uv[i]).squaredNorm() <= r2 && ++support >= options.min_support) break;
    if (support < options.min_support) (*isolated)[i] = 1, ++marked;
  }
  return marked;
}

}  // namespace slamkit
