// What `slamkit optimize INPUT` (and the Python load_pose_graph) loads: a pose-graph file in any
// supported format, or a built-in generated graph named by a sim: spec ("sim:sphere",
// "sim:manhattan?seed=3", "sim:calib2d?laps=2", ...; sim/pose_graph_generator.h and
// sim/calibration_generator.h list the parameters).
#pragma once

#include <string>

#include "slamkit/core/pose_graph.h"
#include "slamkit/io/pose_graph_io.h"

namespace slamkit {

/// A generated graph gets source = spec, format "g2o" (what it would be written as) and a report
/// with the information check, like a file. Throws InputError (file, line, field) as the readers do.
PoseGraph load_pose_graph(const std::string& spec, const PoseGraphReadOptions& options = {},
                          PoseGraphReadReport* report = nullptr);

}  // namespace slamkit
