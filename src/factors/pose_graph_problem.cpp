#include "slamkit/factors/pose_graph_problem.h"

#include "slamkit/core/error.h"
#include "slamkit/core/information.h"
#include "slamkit/factors/pose_point_factor.h"

namespace slamkit {

PoseGraphProblem build_pose_graph_problem(const PoseGraph& g, const PoseGraphProblemOptions& options,
                                          const std::vector<std::int64_t>* gauge,
                                          const std::vector<std::string>* gauge_notes) {
  PoseGraphProblem p;
  std::size_t params = 0;
  for (const GraphVertex& v : g.vertices())
    params += v.kind == VertexKind::kPose2   ? ManifoldTraits<SE2>::kAmbient
              : v.kind == VertexKind::kPose3 ? ManifoldTraits<SE3>::kAmbient
                                             : (v.kind == VertexKind::kPoint2 ? 2 : 3);
  p.values.reserve(g.vertices().size(), params);  // calibration variables, if any, regrow it once
  p.graph.reserve(g.edges.size());
  for (const GraphVertex& v : g.vertices()) {
    if (!v.has_estimate)
      throw InputError(g.source, v.line, "id", "vertex " + std::to_string(v.id) + " has no initial estimate");
    const Key k = vertex_key(v.id);
    switch (v.kind) {
      case VertexKind::kPose2: p.values.insert(k, v.pose2); break;
      case VertexKind::kPose3: p.values.insert(k, v.pose3); break;
      case VertexKind::kPoint2: p.values.insert(k, Eigen::Vector2d(v.point.head<2>())); break;
      case VertexKind::kPoint3: p.values.insert(k, v.point); break;
    }
  }
  add_calibration_to_problem(g, options.calibration, p.values, p.graph, p.calibration);
  // Noise models are immutable: an edge with the same information as the previous one shares
  // its model (most files use one information matrix for all or runs of edges).
  const Eigen::MatrixXd* previous_information = nullptr;
  std::shared_ptr<const NoiseModel> previous_noise;
  for (const GraphEdge& e : g.edges) {
    std::shared_ptr<const NoiseModel> noise;
    if (previous_information && previous_information->rows() == e.information.rows() &&
        previous_information->cols() == e.information.cols() && *previous_information == e.information) {
      noise = previous_noise;
    } else {
      try {
        noise = NoiseModel::information(e.information);
      } catch (const NumericalError&) {
        const InformationCheck c = check_information(e.information);
        throw InputError(g.source, e.line, "information",
                         std::string("information matrix of edge ") + std::to_string(e.from) + "-" +
                             std::to_string(e.to) + " is " + to_string(c.status) + " (min eigenvalue " +
                             std::to_string(c.min_eigenvalue) + "); use --repair-information to project it to the PSD cone");
      }
      previous_information = &e.information;
      previous_noise = noise;
    }
    const auto kernel = (options.kernel_on_odometry || !is_odometry(e)) ? options.kernel : nullptr;
    if (e.calibrated) {
      p.graph.add(make_calibrated_factor(e, noise, kernel));
      continue;
    }
    const Key a = vertex_key(e.from), b = vertex_key(e.to);
    switch (e.kind) {
      case EdgeKind::kPose2Pose2: p.graph.emplace<BetweenFactorSE2>(a, b, e.pose2, noise, kernel); break;
      case EdgeKind::kPose3Pose3:
        p.graph.emplace<BetweenFactorSE3>(a, b, e.pose3, noise, kernel, options.se3_error);
        break;
      case EdgeKind::kPose2Point2:
        p.graph.emplace<PosePointFactor2>(a, b, Eigen::Vector2d(e.point.head<2>()), noise, kernel);
        break;
      case EdgeKind::kPose3Point3: {
        const auto it = g.sensor_offsets.find(e.sensor_offset_id);
        const SE3 offset = it == g.sensor_offsets.end() ? SE3() : it->second;
        p.graph.emplace<PosePointFactor3>(a, b, e.point, offset, noise, kernel);
        break;
      }
    }
  }
  if (gauge) {
    p.gauge = *gauge;
    if (gauge_notes) p.notes.insert(p.notes.end(), gauge_notes->begin(), gauge_notes->end());
  } else {
    p.gauge = gauge_vertices(g, &p.notes);
  }
  for (std::int64_t id : p.gauge) p.values.set_fixed(vertex_key(id));
  return p;
}

void copy_estimates(const Values& values, PoseGraph& g) {
  for (std::size_t i = 0; i < g.vertices().size(); ++i) {
    GraphVertex& v = g.vertex_at(i);
    const Key k = vertex_key(v.id);
    switch (v.kind) {
      case VertexKind::kPose2: v.pose2 = values.at<SE2>(k); break;
      case VertexKind::kPose3: v.pose3 = values.at<SE3>(k); break;
      case VertexKind::kPoint2: v.point.head<2>() = values.at<Eigen::Vector2d>(k); break;
      case VertexKind::kPoint3: v.point = values.at<Eigen::Vector3d>(k); break;
    }
    v.has_estimate = true;
  }
  copy_calibration_estimates(values, g);
}

}  // namespace slamkit
