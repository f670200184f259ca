// Named visual-inertial sequences of the simulator (docs/simulator.md): the real paths the
// simulator replays and the sensors it simulates, as files under the datasets folder
// (SLAMKIT_DATA, default ../shared/datasets):
//   room1..room4     vio/tumvi/gt/dataset-roomN_512_16.csv, TUM-VI cam0 (equidistant fisheye,
//                    mask circle 300 px) and BMI160 IMU noise from vio/tumvi/calib
//   euroc:V1_01, euroc:V1_02, euroc:V2_03
//                    vio/euroc/gt/*.csv, EuRoC cam0 (radtan) and ADIS16448 noise from vio/euroc/calib
//   any other spec   a trajectory file (TUM, EuRoC CSV) with the TUM-VI sensors
// `slamkit simulate --vi` and `slamkit vio --sim` share this table (io/visual_inertial_sequence_io.h
// reads the files and runs the simulator).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace slamkit {

struct VisualInertialSequence {
  std::string name;                  ///< the spec as given
  std::filesystem::path trajectory;  ///< the real path (TUM or EuRoC CSV)
  std::filesystem::path camchain;    ///< Kalibr camchain (cam0 used)
  std::filesystem::path imu;         ///< Kalibr IMU noise file
  double mask_radius_px = 0.0;       ///< fisheye mask circle (0: none)
  bool named = false;                ///< one of the names above (not a file)
};

/// The names above, in table order.
const std::vector<std::string>& visual_inertial_sequence_names();
bool is_visual_inertial_sequence_name(const std::string& spec);

/// option if not empty, else $SLAMKIT_DATA if set, else ../shared/datasets.
std::filesystem::path visual_inertial_data_root(const std::string& option = "");

/// The files of `spec` under `root`. An unknown name that looks like one (euroc:..., room...
/// that is not a file) throws InputError (field "vi") listing the names.
VisualInertialSequence resolve_visual_inertial_sequence(const std::string& spec, const std::filesystem::path& root);

}  // namespace slamkit
