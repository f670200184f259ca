// Small helpers shared by the subcommands: JSON output files and timing.
#pragma once

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/sim/calibration_generator.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit::cli {

/// Writes j (pretty-printed) to path; "-" writes to stdout. Throws InputError if it cannot.
inline void write_json(const std::string& path, const nlohmann::json& j) {
  if (path == "-") {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "", "cannot write JSON output");
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path, 0, "", "error while writing JSON output");
}

/// A pose-graph file, or a built-in generated graph named "sim:sphere", "sim:manhattan", ...
inline PoseGraph load_pose_graph(const std::string& spec, const PoseGraphReadOptions& options,
                                 PoseGraphReadReport* report) {
  PoseGraphSimOptions sim;
  CalibrationSimOptions calib;
  const bool is_calib = parse_calibration_sim_spec(spec, &calib);
  if (is_calib || parse_sim_spec(spec, &sim)) {
    PoseGraph g = is_calib ? generate_calibration_problem(calib) : generate_pose_graph(sim);
    g.source = spec;
    g.format = "g2o";  // what it would be written as
    if (report) {
      *report = PoseGraphReadReport{};
      report->format = PoseGraphFormat::kG2o;
      report->information = check_information(g);
    }
    return g;
  }
  return read_pose_graph(spec, options, report);
}

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace slamkit::cli
