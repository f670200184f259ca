#include "slamkit/sim/visual_inertial_sequences.h"

#include <cstdlib>
#include <map>

#include "slamkit/core/error.h"
#include "slamkit/core/path_query.h"

namespace slamkit {
namespace {

namespace fs = std::filesystem;

// The TUM-VI cam0 mask (openvins_mask_tumvi0.png) hides pixels beyond 304–310 px from the
// principal point; 300 px keeps features off its border.
constexpr double kTumViMask = 300.0;

const std::map<std::string, std::string>& rooms() {
  static const std::map<std::string, std::string> m = {
      {"room1", "dataset-room1_512_16.csv"}, {"room2", "dataset-room2_512_16.csv"},
      {"room3", "dataset-room3_512_16.csv"}, {"room4", "dataset-room4_512_16.csv"}};
  return m;
}

const std::map<std::string, std::string>& euroc() {
  static const std::map<std::string, std::string> m = {{"euroc:V1_01", "V1_01_easy_gt_20hz.csv"},
                                                       {"euroc:V1_02", "V1_02_medium_gt.csv"},
                                                       {"euroc:V2_03", "V2_03_difficult_gt.csv"}};
  return m;
}

}  // namespace

const std::vector<std::string>& visual_inertial_sequence_names() {
  static const std::vector<std::string> names = {"room1", "room2", "room3", "room4",
                                                 "euroc:V1_01", "euroc:V1_02", "euroc:V2_03"};
  return names;
}

bool is_visual_inertial_sequence_name(const std::string& spec) { return rooms().count(spec) || euroc().count(spec); }

fs::path visual_inertial_data_root(const std::string& option) {
  if (!option.empty()) return option;
  const char* env = std::getenv("SLAMKIT_DATA");
  return env && *env ? fs::path(env) : fs::path("../shared/datasets");
}

VisualInertialSequence resolve_visual_inertial_sequence(const std::string& spec, const fs::path& root) {
  const fs::path vio = root / "vio";
  VisualInertialSequence s;
  s.name = spec;
  s.camchain = vio / "tumvi/calib/openvins_kalibr_imucam_chain.yaml";
  s.imu = vio / "tumvi/calib/openvins_kalibr_imu_chain.yaml";
  s.mask_radius_px = kTumViMask;
  if (const auto it = rooms().find(spec); it != rooms().end()) {
    s.trajectory = vio / "tumvi/gt" / it->second;
    s.named = true;
    return s;
  }
  if (const auto it = euroc().find(spec); it != euroc().end()) {
    s.trajectory = vio / "euroc/gt" / it->second;
    s.camchain = vio / "euroc/calib/openvins_kalibr_imucam_chain.yaml";
    s.imu = vio / "euroc/calib/openvins_kalibr_imu_chain.yaml";
    s.mask_radius_px = 0.0;
    s.named = true;
    return s;
  }
  if (spec.rfind("euroc:", 0) == 0 || (spec.rfind("room", 0) == 0 && !path_exists(spec))) {
    std::string names;
    for (const std::string& n : visual_inertial_sequence_names()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("", 0, "vi", "unknown sequence '" + spec + "' (" + names + " or a trajectory file)");
  }
  s.trajectory = spec;
  return s;
}

}  // namespace slamkit
