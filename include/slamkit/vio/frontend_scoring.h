// Scoring of the dynamic-feature classifier against ground truth (docs/frontend.md).
// A feature's truth comes from the label image at its (rounded) pixel: 0 static, > 0 the id of a
// moving object. With a speed map, an object slower than min_speed_mps is "excluded": a feature on
// it counts neither as a miss nor as a false alarm (issue 13 scores objects faster than 0.3 m/s).
//   true positive   flagged dynamic, on a counted moving object
//   false positive  flagged dynamic, on the static scene
//   false negative  not flagged dynamic (static or unknown), on a counted moving object
//   true negative   not flagged dynamic, on the static scene
// precision = tp / (tp + fp), recall = tp / (tp + fn); each is 1 when its denominator is 0
// (nothing flagged / nothing to find) and the counts say so.
#pragma once

#include <Eigen/Core>
#include <map>
#include <vector>

#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/gray_image.h"

namespace slamkit {

struct DetectionScoreOptions {
  std::map<int, double> label_speed_mps;  ///< object id -> speed; ids not listed are counted
  double min_speed_mps = 0.3;
};

struct DetectionScore {
  long true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0;
  long excluded = 0;       ///< on a moving object slower than min_speed_mps
  long unknown = 0;        ///< flagged unknown (also counted above as "not dynamic")
  long outside = 0;        ///< pixel outside the label image (not scored)
  double precision() const;
  double recall() const;
  DetectionScore& operator+=(const DetectionScore& o);
};

/// Scores the flags of the features at pixels uv against the label image. Throws
/// std::invalid_argument if uv and flags differ in size.
DetectionScore score_against_labels(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                                    const LabelImage& labels, const DetectionScoreOptions& options = {});
/// The same with one label per feature (feature-level simulations without images).
DetectionScore score_against_feature_labels(const std::vector<int>& labels, const std::vector<FeatureMotion>& flags,
                                            const DetectionScoreOptions& options = {});

}  // namespace slamkit
