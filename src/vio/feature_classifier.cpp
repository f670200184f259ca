#include "slamkit/vio/feature_classifier.h"

#include <set>
#include <string>

#include "slamkit/core/error.h"

namespace slamkit {

SimLabelClassifier::SimLabelClassifier(const VisualInertialSim& sim) : sim_(sim) {
  for (const SimLandmark& l : sim.landmarks) group_of_landmark_[l.id] = l.group;
}

void SimLabelClassifier::classify(std::size_t frame_index, CameraFrame& frame) {
  if (frame_index >= sim_.frames.size())
    throw InputError(sim_.source, 0, "frames", "frame " + std::to_string(frame_index) + " is not in the simulation");
  const SimFrame& f = sim_.frames[frame_index];
  std::unordered_map<std::int64_t, const SimObservation*> by_track;
  for (const SimObservation& o : f.observations) by_track[o.track_id] = &o;
  std::set<int> groups;
  for (FeatureObservation& o : frame.features) {
    const auto it = by_track.find(static_cast<std::int64_t>(o.track_id));
    if (it == by_track.end())
      throw InputError(sim_.source, 0, "track", "track " + std::to_string(o.track_id) + " is not in frame " +
                                                    std::to_string(frame_index));
    o.dynamic = it->second->dynamic;
    if (o.dynamic) {
      const auto g = group_of_landmark_.find(it->second->landmark_id);
      groups.insert(g == group_of_landmark_.end() ? -1 : g->second);
    }
  }
  frame.dynamic_groups = static_cast<int>(groups.size());
}

}  // namespace slamkit
