// Scoring of the dynamic-feature classifier against ground truth (docs/frontend.md).
// A feature's truth comes from the label image (0 static, > 0 the id of a moving object), by one
// of two rules (docs/frontend.md, "Scoring"):
//   centre (patch_half_size_px = 0): the label at the feature's rounded pixel;
//   patch  (patch_half_size_px = h > 0): the labels of the (2h+1)² square about it, the patch KLT
//     tracks (h = klt_window / 2). All 0 ⇒ static; all > 0 ⇒ moving (object = the centre's label,
//     else the most frequent one); both ⇒ "mixed": the patch straddles a silhouette, its motion is
//     neither the object's nor the background's, so it is counted (mixed, mixed_flagged) but is
//     neither a hit, a miss nor a false alarm. Pixels outside the image are not part of the patch. With a speed map, an object slower than min_speed_mps is "excluded": a feature on
// it counts neither as a miss nor as a false alarm (issue 13 scores objects faster than 0.3 m/s).
// With a distance map (object id -> its distance from the camera in the scored frame), an object
// outside [min_distance_m, max_distance_m] is excluded the same way (issue 13: "at 2–6 m"); ids
// not in the map are scored at any distance. Features on the static scene are always scored.
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
  /// object id -> distance from the camera in the scored frame [m]; ids not listed are counted
  std::map<int, double> label_distance_m;
  double min_distance_m = 2.0, max_distance_m = 6.0;  ///< objects outside are excluded (issue 13: 2–6 m)
  int patch_half_size_px = 0;  ///< 0: centre-pixel rule; h > 0: the (2h+1)² patch rule (see above)
};

struct DetectionScore {
  long true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0;
  long excluded = 0;       ///< on a moving object slower than min_speed_mps
  long excluded_range = 0; ///< on a moving object (fast enough) outside the distance range
  long unknown = 0;        ///< flagged unknown (also counted above as "not dynamic")
  long outside = 0;        ///< pixel outside the label image (not scored)
  long mixed = 0;          ///< patch rule: the patch holds static and moving pixels (not scored)
  long mixed_flagged = 0;  ///< of those, flagged dynamic
  double precision() const;
  double recall() const;
  DetectionScore& operator+=(const DetectionScore& o);
};

/// Scores the flags of the features at pixels uv against the label image. Throws
/// std::invalid_argument if uv and flags differ in size.
DetectionScore score_against_labels(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                                    const LabelImage& labels, const DetectionScoreOptions& options = {});
/// Truth of one feature: 0 static, > 0 the object id, kMixedTruth, or kOutsideTruth (pixel outside
/// the image); patch_half_size_px as in DetectionScoreOptions.
constexpr int kMixedTruth = -1, kOutsideTruth = -2;
int label_truth(const LabelImage& labels, const Eigen::Vector2d& uv, int patch_half_size_px);
/// Truth of a track tested between two frames, from the truths of its two ends: outside if either
/// is; both static ⇒ static; both on objects ⇒ the current object; otherwise (a mixed end, or one
/// end on an object and the other on the background: an occlusion) mixed.
int track_truth(int then, int now);
/// Adds one feature of truth `truth` (as above) and flag to the score.
void add_to_score(int truth, FeatureMotion flag, const DetectionScoreOptions& options, DetectionScore* score);
/// The same with one label per feature (feature-level simulations without images).
DetectionScore score_against_feature_labels(const std::vector<int>& labels, const std::vector<FeatureMotion>& flags,
                                            const DetectionScoreOptions& options = {});

}  // namespace slamkit
