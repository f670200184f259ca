#include "slamkit/filters/filter_factory.h"

#include "slamkit/core/error.h"
#include "slamkit/filters/ekf_slam.h"
#include "slamkit/filters/eif.h"

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
  if (name == "fastslam1" || name == "fastslam2")
    throw InputError("--algorithm", 0, "algorithm",
                     name + " is not built in this branch (FastSLAM comes with the fastslam branch)");
  throw InputError("--algorithm", 0, "algorithm",
                   "unknown filter \"" + name + "\" (ekf, eif, seif, seif-entropy, fastslam1, fastslam2)");
}

std::vector<std::string> landmark_filter_names() {
  return {"ekf", "eif", "seif", "seif-entropy", "fastslam1", "fastslam2"};
}

}  // namespace slamkit
