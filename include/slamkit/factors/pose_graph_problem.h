// From a PoseGraph dataset to a FactorGraph problem and back.
//
// Each vertex becomes a variable keyed by its id (SE2/SE3 poses, Vector2/3 landmarks); each
// edge a between or pose–point factor with its information matrix as noise model; the gauge
// vertices (core/pose_graph.h: FIX, else the smallest id per component) are held fixed.
#pragma once

#include <string>
#include <vector>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/pose_graph.h"
#include "slamkit/factors/between_factor.h"
#include "slamkit/factors/calibration_problem.h"

namespace slamkit {

struct PoseGraphProblemOptions {
  std::shared_ptr<const RobustKernel> kernel;  ///< robust kernel on the edges (none: least squares)
  bool kernel_on_odometry = true;              ///< false: only loop closures get the kernel
  Se3ErrorForm se3_error = Se3ErrorForm::kQuaternion;
  CalibrationOptions calibration;  ///< which calibration variables are free (factors/calibration_problem.h)
};

struct PoseGraphProblem {
  FactorGraph graph;
  Values values;
  std::vector<std::int64_t> gauge;  ///< fixed vertex ids
  std::vector<std::string> notes;   ///< choices made (gauge), to show the user
  std::vector<CalibrationVariable> calibration;  ///< inserted after the vertices, in this order
};

inline Key vertex_key(std::int64_t id) { return static_cast<Key>(id); }

/// Throws InputError (naming the edge's line) if an information matrix is not positive
/// definite or a vertex has no estimate.
/// `gauge` (with its notes), when the caller already chose it with gauge_vertices(), is used as is.
PoseGraphProblem build_pose_graph_problem(const PoseGraph& g, const PoseGraphProblemOptions& options = {},
                                          const std::vector<std::int64_t>* gauge = nullptr,
                                          const std::vector<std::string>* gauge_notes = nullptr);

/// Copies the variables' values back into the graph's vertex estimates (and its calibration).
void copy_estimates(const Values& values, PoseGraph& g);

}  // namespace slamkit
