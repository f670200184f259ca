#include "slamkit/io/pose_graph_source.h"

#include "slamkit/core/information.h"
#include "slamkit/sim/calibration_generator.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit {

PoseGraph load_pose_graph(const std::string& spec, const PoseGraphReadOptions& options,
                          PoseGraphReadReport* report) {
  PoseGraphSimOptions sim;
  CalibrationSimOptions calib;
  const bool is_calib = parse_calibration_sim_spec(spec, &calib);
  if (!is_calib && !parse_sim_spec(spec, &sim)) return read_pose_graph(spec, options, report);
  PoseGraph g = is_calib ? generate_calibration_problem(calib) : generate_pose_graph(sim);
  g.source = spec;
  g.format = "g2o";
  if (report) {
    *report = PoseGraphReadReport{};
    report->format = PoseGraphFormat::kG2o;
    report->information = check_information(g);
  }
  return g;
}

}  // namespace slamkit
