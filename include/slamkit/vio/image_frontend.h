// ImageFrontend: the DVI front end on a stream of images (docs/frontend.md, "Long baseline"):
// FeatureTracker (detection, KLT) then DynamicFeatureFilter over a longer baseline than one frame.
//
// Why: the epipolar distance of a moving point grows with the time between the two frames it is
// measured on. At 20 Hz with the TUM-VI fisheye (f ≈ 191 px) a person 4 m away walking 0.3 m/s
// moves 0.7 px per frame, under the 1 px threshold; over k frames it moves k times as far while
// the static points' distance stays at the tracking noise.
// Per frame t, a feature alive since frame t − a (age a ≥ k) is classified on the baseline k: the
// matches (p_{t−k}, p_t) of all tracks alive over k frames give F_k by RANSAC; younger features
// (0 < a < k) take their flag from the frame-to-frame test (F_1 on all tracked features), so
// two filter runs per frame at most (with every b in 1..k the classification cost grew k-fold).
// New features (age 0) are unknown. With sticky_dynamic a track once flagged dynamic stays so
// (moving objects rarely stop; a flag lost at a short baseline is not a change of motion).
// M = static / (static + dynamic) over the features of the frame.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/feature_tracker.h"

namespace slamkit {

struct ImageFrontendOptions {
  FeatureTrackerOptions tracker;
  DynamicFilterOptions filter;
  int baseline_frames = 4;      ///< k: the longest baseline of the epipolar test (1: frame to frame)
  bool sticky_dynamic = false;  ///< a track flagged dynamic once stays dynamic (measured: worse precision)
};

struct FrontendFeature {
  std::int64_t id = -1;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< raw (distorted) pixel in the current frame
  FeatureMotion motion = FeatureMotion::kUnknown;
  int baseline = 0;  ///< frames between the two views it was classified on (0: not classified)
};

struct FrontendFrameResult {
  std::vector<FrontendFeature> features;
  TrackingResult tracking;  ///< counts of the tracker (its features are the same as above)
  double static_ratio = 1.0;
  int n_static = 0, n_dynamic = 0, n_unknown = 0;
  /// Status of the longest baseline run this frame (kTooFewMatches when none could run).
  ClassificationStatus status = ClassificationStatus::kTooFewMatches;
  double tracking_ms = 0.0, classification_ms = 0.0;  ///< wall clock
};

class ImageFrontend {
 public:
  /// camera: the images' model (undistortion); mask: empty or the frames' size, non-zero where
  /// corners may be detected. Throws std::invalid_argument on bad options (baseline_frames < 1).
  ImageFrontend(ImageFrontendOptions options, std::shared_ptr<const CameraModel> camera, GrayImage mask = {});
  /// Tracks and classifies the next frame. Throws std::invalid_argument on an empty frame or one
  /// whose size differs from the previous one (FeatureTracker).
  FrontendFrameResult process(const GrayImage& frame);
  const ImageFrontendOptions& options() const { return options_; }

 private:
  ImageFrontendOptions options_;
  FeatureTracker tracker_;
  DynamicFeatureFilter filter_;
  /// history_[j]: positions of the features tracked in frame t − 1 − j (j < k).
  std::deque<std::unordered_map<std::int64_t, Eigen::Vector2d>> history_;
  std::unordered_set<std::int64_t> flagged_dynamic_;
};

/// A detection mask for a fisheye image: non-zero inside the circle of radius (radius_px − margin_px)
/// about the principal point (cx, cy); radius 0 gives an empty mask (whole image usable).
GrayImage circular_mask(int width, int height, double cx, double cy, double radius_px, double margin_px = 8.0);

}  // namespace slamkit
