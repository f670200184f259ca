// A classification whose epipolar lines are the image rows (a camera moving along x: l = (1, 0, 0) ×
// p1 = (0, −1, y1), the row y = y1), with given flags, for the front-end tests on synthetic pairs.
#pragma once

#include <vector>

#include "slamkit/vio/dynamic_feature_filter.h"

namespace slamkit::testing {

inline Classification rows_as_epipolar_lines(const std::vector<FeatureMotion>& flags, double distance_px) {
  Classification c;
  c.status = ClassificationStatus::kEpipolar;
  c.F << 0, 0, 0, 0, 0, -1, 0, 1, 0;
  c.flags = flags;
  c.distance_px.assign(flags.size(), distance_px);
  for (FeatureMotion f : flags) (f == FeatureMotion::kStatic ? c.n_static : c.n_dynamic)++;
  c.static_ratio = double(c.n_static) / flags.size();
  return c;
}

}  // namespace slamkit::testing
