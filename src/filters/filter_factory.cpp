#include "slamkit/filters/filter_factory.h"

#include "slamkit/core/error.h"
#include "slamkit/filters/ekf_slam.h"
#include "slamkit/filters/eif.h"
#include "slamkit/filters/fastslam.h"

namespace slamkit {

std::unique_ptr<LandmarkFilter> make_landmark_filter(const std::string& name, const LandmarkFilterOptions& options,
                                                     const SeifOptions& seif) {
  if (name == "ekf") return std::make_unique<EkfSlam>(options);
  if (name == "eif") return std::make_unique<Eif>(options);
  if (name == "seif" || name == "seif-entropy") {
    SeifOptions s = seif;
    s.rule = name == "seif" ? SparsificationRule::kStandard : SparsificationRule::kEntropy;
    return std::make_unique<Seif>(options, s);
  }
  if (name == "fastslam1" || name == "fastslam2") {
    if (!options.motion) throw InputError("filter options", 0, "motion", "no motion model");
    FastSlamOptions f;
    f.version = name == "fastslam1" ? 1 : 2;
    f.particles = options.particles;
    f.seed = options.seed;
    f.initial_pose = options.initial_pose;
    f.initial_covariance = options.initial_sigma.cwiseAbs2().asDiagonal();
    f.new_landmark_distance2 = options.association.new_landmark_distance2;
    switch (options.association.method) {
      case AssociationMethod::kKnown: f.association = FastSlamAssociation::kKnown; break;
      case AssociationMethod::kNearestNeighbour: f.association = FastSlamAssociation::kNearestNeighbour; break;
      default:
        throw InputError("--association", 0, "association",
                         "FastSLAM associates per particle: known or nn (JCBB is for the Gaussian filters)");
    }
    return std::make_unique<FastSlam>(options.motion, options.sensor, f);
  }
  throw InputError("--algorithm", 0, "algorithm",
                   "unknown filter \"" + name + "\" (ekf, eif, seif, seif-entropy, fastslam1, fastslam2)");
}

std::vector<std::string> landmark_filter_names() {
  return {"ekf", "eif", "seif", "seif-entropy", "fastslam1", "fastslam2"};
}

}  // namespace slamkit
