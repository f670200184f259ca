// Precision/recall of "dynamic" against per-pixel or per-feature labels (see the header).
#include "slamkit/vio/frontend_scoring.h"

#include <cmath>
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
  excluded += o.excluded, unknown += o.unknown, outside += o.outside;
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
    ++(flagged ? s->true_positive : s->false_negative);
  } else {
    ++(flagged ? s->false_positive : s->true_negative);
  }
}

void check_sizes(std::size_t a, std::size_t b) {
  if (a != b)
    throw std::invalid_argument("frontend scoring: " + std::to_string(a) + " features but " + std::to_string(b) + " flags");
}

}  // namespace

DetectionScore score_against_labels(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                                    const LabelImage& labels, const DetectionScoreOptions& options) {
  check_sizes(uv.size(), flags.size());
  if (labels.labels.size() != std::size_t(labels.width) * std::size_t(labels.height))
    throw std::invalid_argument("frontend scoring: the label image's size is not width x height");
  DetectionScore s;
  for (std::size_t i = 0; i < uv.size(); ++i) {
    const double x = std::round(uv[i].x()), y = std::round(uv[i].y());
    if (!(x >= 0 && y >= 0 && x < labels.width && y < labels.height)) {
      ++s.outside;
      continue;
    }
    add(labels.at(int(x), int(y)), flags[i], options, &s);
  }
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
