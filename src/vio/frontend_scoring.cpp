// Precision/recall of "dynamic" against per-pixel or per-feature labels (see the header).
#include "slamkit/vio/frontend_scoring.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace slamkit {

double DetectionScore::precision() const {
  const long d = true_positive + false_positive;
  return d > 0 ? double(true_positive) / d : 1.0;
}

double DetectionScore::recall() const {
  const long d = true_positive + false_negative;
  return d > 0 ? double(true_positive) / d : 1.0;
}

DetectionScore& DetectionScore::operator+=(const DetectionScore& o) {
  true_positive += o.true_positive, false_positive += o.false_positive;
  false_negative += o.false_negative, true_negative += o.true_negative;
  excluded += o.excluded, excluded_range += o.excluded_range, unknown += o.unknown, outside += o.outside;
  mixed += o.mixed, mixed_flagged += o.mixed_flagged;
  return *this;
}

namespace {

void add(int label, FeatureMotion flag, const DetectionScoreOptions& o, DetectionScore* s) {
  if (flag == FeatureMotion::kUnknown) ++s->unknown;
  const bool flagged = flag == FeatureMotion::kDynamic;
  if (label > 0) {
    const auto speed = o.label_speed_mps.find(label);
    if (speed != o.label_speed_mps.end() && speed->second < o.min_speed_mps) {
      ++s->excluded;
      return;
    }
    const auto distance = o.label_distance_m.find(label);
    if (distance != o.label_distance_m.end() &&
        !(distance->second >= o.min_distance_m && distance->second <= o.max_distance_m)) {
      ++s->excluded_range;
      return;
    }
    ++(flagged ? s->true_positive : s->false_negative);
  } else {
    ++(flagged ? s->false_positive : s->true_negative);
  }
}

// Patch rule: the label of the (2h+1)² patch about (x, y): 0 all static, > 0 all moving (the
// centre's id, else the most frequent), -1 mixed.
int patch_label(const LabelImage& labels, int x, int y, int h) {
  bool any_static = false;
  std::map<int, int> moving;
  for (int v = std::max(0, y - h); v <= std::min(labels.height - 1, y + h); ++v)
    for (int u = std::max(0, x - h); u <= std::min(labels.width - 1, x + h); ++u) {
      const int l = labels.at(u, v);
      if (l > 0) ++moving[l];
      else any_static = true;
    }
  if (moving.empty()) return 0;
  if (any_static) return -1;
  const int centre = labels.at(x, y);
  if (centre > 0) return centre;
  int best = 0, count = 0;
  for (const auto& [id, n] : moving)
    if (n > count) best = id, count = n;
  return best;
}

void check_sizes(std::size_t a, std::size_t b) {
  if (a != b)
    throw std::invalid_argument("frontend scoring: " + std::to_string(a) + " features but " + std::to_string(b) + " flags");
}

}  // namespace

int label_truth(const LabelImage& labels, const Eigen::Vector2d& uv, int patch_half_size_px) {
  const double x = std::round(uv.x()), y = std::round(uv.y());
  if (!(x >= 0 && y >= 0 && x < labels.width && y < labels.height)) return kOutsideTruth;
  return patch_half_size_px > 0 ? patch_label(labels, int(x), int(y), patch_half_size_px) : labels.at(int(x), int(y));
}

int track_truth(int then, int now) {
  if (then == kOutsideTruth || now == kOutsideTruth) return kOutsideTruth;
  if (then == kMixedTruth || now == kMixedTruth) return kMixedTruth;
  if ((then > 0) != (now > 0)) return kMixedTruth;
  return now;
}

void add_to_score(int truth, FeatureMotion flag, const DetectionScoreOptions& options, DetectionScore* s) {
  if (truth == kOutsideTruth) {
    ++s->outside;
  } else if (truth == kMixedTruth) {
    if (flag == FeatureMotion::kUnknown) ++s->unknown;
    ++s->mixed;
    s->mixed_flagged += flag == FeatureMotion::kDynamic;
  } else {
    add(truth, flag, options, s);
  }
}

DetectionScore score_against_labels(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                                    const LabelImage& labels, const DetectionScoreOptions& options) {
  check_sizes(uv.size(), flags.size());
  if (labels.labels.size() != std::size_t(labels.width) * std::size_t(labels.height))
    throw std::invalid_argument("frontend scoring: the label image's size is not width x height");
  DetectionScore s;
  for (std::size_t i = 0; i < uv.size(); ++i)
    add_to_score(label_truth(labels, uv[i], options.patch_half_size_px), flags[i], options, &s);
  return s;
}

DetectionScore score_against_feature_labels(const std::vector<int>& labels, const std::vector<FeatureMotion>& flags,
                                            const DetectionScoreOptions& options) {
  check_sizes(labels.size(), flags.size());
  DetectionScore s;
  for (std::size_t i = 0; i < labels.size(); ++i) add(labels[i], flags[i], options, &s);
  return s;
}

}  // namespace slamkit
