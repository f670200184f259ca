// Dynamic groups: a dynamic flag stands only where the frame shows a moving object, i.e. where
// other features nearby are flagged too (docs/frontend.md, "Session 36").
//
// A mover seen by the front end is a textured surface several features wide (the detector keeps
// features min_distance apart, so an object of a few such spacings carries several of them), and
// its features break the epipolar constraint together. A static false alarm is a property of one
// track: a T-junction of two surfaces at different depths, a track slipped along an edge, a corner
// that is no 3-D point. So a flag with no other flagged feature within `radius_px` is *isolated*:
// an unreliable track rather than a moving object. It is not reported as dynamic (no moving object
// is claimed there) and not used as static either: the estimator leaves it out as before. P4
// speaks of the frame's dynamic *groups*; this is the smallest group rule: a flag needs at least
// min_support other flags within radius_px. Neighbours are counted among the flags before the
// rule (one pass: the result does not depend on the order).
// A *turned* flag (session 38) is one on a track whose last tests were static: a track that held
// the camera's motion and now breaks it has most often slipped (a walker's silhouette passing over
// its patch, an edge), while a mover's features are flagged test after test from their first one;
// such a flag needs turned_min_support other flags to stand (a walker that starts to move, or
// turns off the epipolar lines, shows several such flags at once).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/vio/dynamic_feature_filter.h"

namespace slamkit {

struct DynamicGroupOptions {
  /// Other dynamic-flagged features a flag needs within radius_px to stand; 0 disables the rule.
  int min_support = 1;
  /// The neighbourhood, as a multiple of the detector's minimum distance between features
  /// (FeatureTrackerOptions::min_distance_px): 2 × 30 px = 60 px by default.
  double radius_factor = 2.0;
  /// The support a turned flag needs (see above; ≥ min_support applies, 0: no extra rule), and
  /// how many static tests in a row before the flag make a track turned (1..16: a track keeps 16).
  int turned_min_support = 2;
  int turned_static_tests = 2;
  /// The neighbourhood in pixels for a detector keeping features min_distance_px apart.
  double radius_px(double min_distance_px) const { return radius_factor * min_distance_px; }
};

/// Throws std::invalid_argument on min_support < 0, turned_min_support < 0, turned_static_tests outside
/// 1..16 or a radius factor that is not finite and > 0.
void check_dynamic_group_options(const DynamicGroupOptions& options);

/// Marks the isolated dynamic flags of one frame: (*isolated)[i] = 1 iff flags[i] == kDynamic and
/// fewer than options.min_support other kDynamic entries of `flags` lie within radius_px of uv[i]
/// (closed), or fewer than max(min_support, turned_min_support) when (*turned)[i] (turned may be
/// null: none). Entries with a non-finite pixel neither count nor are marked. Returns how many were
/// marked (0 when min_support is 0). Throws std::invalid_argument when uv, flags (and turned) differ
/// in size.
int mark_isolated_flags(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                        const DynamicGroupOptions& options, double radius_px, std::vector<char>* isolated,
                        const std::vector<char>* turned = nullptr);

}  // namespace slamkit
