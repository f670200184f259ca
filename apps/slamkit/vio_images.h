// `slamkit vio --sim NAME --images [--image-dir DIR]` (issue 13): renders the frames of the named
// sequence in memory (or reads the folder `slamkit simulate --images DIR` wrote for the same
// seed / dynamic level / duration), runs the DVI front end on the pixels (vio/image_vio.h) and
// returns the run whose observations are the front end's tracks, with the front end's JSON
// (kind "frontend" keys: detection score against the pixel labels, M, timings) for `slamkit vio`.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "slamkit/sim/visual_inertial_sim.h"
#include "slamkit/vio/image_vio.h"

namespace slamkit::cli {

struct VioImageCliOptions {
  std::string sim, data, image_dir;
  std::string feature_log;  ///< CSV of every scored feature (empty: none)
  std::uint64_t seed = 1;
  std::string dynamic = "none";
  double duration = 0.0;
  int threads = 0;  ///< renderer threads (0: hardware)
  bool quiet = false;
  ImageVioOptions vio;
};

/// The tracked run; *frontend receives the JSON object (stored under "frontend" by the caller).
/// The epipolar re-search options as the CLI got them: InputError naming `option` (before any
/// work) where check_epipolar_search_options would throw later.
void check_epipolar_search_input(const EpipolarSearchOptions& o, const char* option);
/// The same for the affine re-alignment's options (InputError naming --affine-realign).
void check_affine_realign_input(const AffineRealignOptions& o);

/// --group-support and --group-radius (the dynamic-group rule, vio/dynamic_groups.h) on `sub`;
/// `scope` prefixes their help ("with --images: ").
void add_dynamic_group_options(CLI::App* sub, DynamicGroupOptions* groups, const std::string& scope);

VisualInertialSim image_vio_run(const VioImageCliOptions& o, nlohmann::json* frontend, std::ostream& log);

}  // namespace slamkit::cli
