#include "slamkit/core/pose_graph_calibration.h"

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit {

bool has_calibration(const PoseGraph& g) {
  if (!g.calibration.empty()) return true;
  for (const GraphEdge& e : g.edges)
    if (e.calibrated) return true;
  return false;
}

namespace {

const CalibrationVertex& vertex_of(const PoseGraph& g, const GraphEdge& e, std::int64_t id, CalibrationKind kind) {
  const CalibrationVertex* v = g.calibration.find(id);
  if (!v || v->kind != kind) {
    throw InputError(g.source, e.line, "calib",
                     std::string(to_string(e.calibrated->kind)) + " needs a " + to_string(kind) +
                         " calibration vertex " + std::to_string(id));
  }
  return *v;
}

// U(K): the effective body-frame motion of an odometry edge.
SE2 odometry_motion(const PoseGraph& g, const GraphEdge& e) {
  const CalibratedMeasurement& c = *e.calibrated;
  if (c.kind == CalibratedEdgeKind::kOdomDifferential) {
    const CalibrationVertex& k = vertex_of(g, e, c.param_a, CalibrationKind::kOdomDifferential);
    return to_se2(differential_drive_motion(k.value, c.odometry[0], c.odometry[1], c.odometry[2]));
  }
  const CalibrationVertex& k = vertex_of(g, e, c.param_a, CalibrationKind::kOdomLinear);
  return to_se2(linear_odometry_motion(Eigen::Matrix<double, 9, 1>(k.value), c.odometry));
}

}  // namespace

SE2 offset2_of(const PoseGraph& g, const GraphEdge& e, std::int64_t id) {
  if (e.calibrated->kind == CalibratedEdgeKind::kSensorOffset2)
    return to_se2(vertex_of(g, e, id, CalibrationKind::kOffset2).value);
  const auto it = g.calibration.offset_parameters2.find(static_cast<int>(id));
  if (it == g.calibration.offset_parameters2.end())
    throw InputError(g.source, e.line, "param_id", "no PARAMS_SE2OFFSET with id " + std::to_string(id));
  return it->second;
}

SE3 offset3_of(const PoseGraph& g, const GraphEdge& e, std::int64_t id) {
  const auto it = g.sensor_offsets.find(static_cast<int>(id));
  if (it == g.sensor_offsets.end())
    throw InputError(g.source, e.line, "param_id", "no PARAMS_SE3OFFSET with id " + std::to_string(id));
  return it->second;
}

void update_calibrated_measurements(PoseGraph& g) {
  for (GraphEdge& e : g.edges) {
    if (!e.calibrated) continue;
    const CalibratedMeasurement& c = *e.calibrated;
    switch (c.kind) {
      case CalibratedEdgeKind::kSensorOffset2:
      case CalibratedEdgeKind::kOffsetParams2:
        e.pose2 = offset2_of(g, e, c.param_a) * c.sensor2 * offset2_of(g, e, c.param_b).inverse();
        break;
      case CalibratedEdgeKind::kOffsetParams3:
        e.pose3 = offset3_of(g, e, c.param_a) * c.sensor3 * offset3_of(g, e, c.param_b).inverse();
        break;
      case CalibratedEdgeKind::kOdomDifferential:
      case CalibratedEdgeKind::kOdomLinear: e.pose2 = odometry_motion(g, e); break;
    }
  }
}

Eigen::VectorXd calibrated_edge_error(const PoseGraph& g, const GraphEdge& e) {
  const CalibratedMeasurement& c = *e.calibrated;
  const GraphVertex& a = g.vertex(e.from);
  const GraphVertex& b = g.vertex(e.to);
  switch (c.kind) {
    case CalibratedEdgeKind::kSensorOffset2:
    case CalibratedEdgeKind::kOffsetParams2:
      return pose2_edge_error(c.sensor2, a.pose2 * offset2_of(g, e, c.param_a), b.pose2 * offset2_of(g, e, c.param_b));
    case CalibratedEdgeKind::kOffsetParams3:
      return pose3_edge_error(c.sensor3, a.pose3 * offset3_of(g, e, c.param_a), b.pose3 * offset3_of(g, e, c.param_b));
    case CalibratedEdgeKind::kOdomDifferential:
    case CalibratedEdgeKind::kOdomLinear: return pose2_edge_error(odometry_motion(g, e), a.pose2, b.pose2);
  }
  throw InputError(g.source, e.line, "", "unknown calibrated edge kind");
}

}  // namespace slamkit
