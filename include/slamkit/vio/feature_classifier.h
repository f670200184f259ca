// DynamicFeatureClassifier: the front end's static/dynamic decision for the features of a frame
// (DVI-SLAM, issue 13), which the sliding-window estimator reads from
// FeatureObservation::dynamic (and CameraFrame::dynamic_groups, for an adaptive θ).
// SimLabelClassifier uses the simulator's labels (a perfect classifier: the feature-level
// experiments); the epipolar classifier on real pixels implements the same interface.
#pragma once

#include <cstddef>
#include <unordered_map>

#include "slamkit/sim/visual_inertial_sim.h"
#include "slamkit/vio/sliding_window_estimator.h"

namespace slamkit {

class DynamicFeatureClassifier {
 public:
  virtual ~DynamicFeatureClassifier() = default;
  /// Sets `dynamic` of every feature of `frame` (frame `frame_index` of the run, in time order)
  /// and, if the classifier knows it, `dynamic_groups`.
  virtual void classify(std::size_t frame_index, CameraFrame& frame) = 0;
};

class SimLabelClassifier final : public DynamicFeatureClassifier {
 public:
  /// Keeps a reference to `sim`, which must outlive the classifier.
  explicit SimLabelClassifier(const VisualInertialSim& sim);
  /// Features are matched to the simulator's observations of frame `frame_index` by track id;
  /// throws InputError if the frame index or a track is not in the simulation.
  void classify(std::size_t frame_index, CameraFrame& frame) override;

 private:
  const VisualInertialSim& sim_;
  std::unordered_map<std::int64_t, int> group_of_landmark_;
};

}  // namespace slamkit
