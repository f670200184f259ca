// Calibrated edges of a PoseGraph (core/calibration.h): their effective measurements and
// their g2o errors at the graph's current pose and calibration estimates.
#pragma once

#include <Eigen/Core>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

/// True if the graph has calibration vertices, SE2 offset parameters or calibrated edges.
bool has_calibration(const PoseGraph& g);

/// The value of offset `id` of a calibrated edge: a calibration vertex for kSensorOffset2, a
/// PARAMS_SE2OFFSET for kOffsetParams2. Throws InputError (naming the edge's line) if absent.
SE2 offset2_of(const PoseGraph& g, const GraphEdge& e, std::int64_t id);
SE3 offset3_of(const PoseGraph& g, const GraphEdge& e, std::int64_t id);

/// Recomputes pose2/pose3 of every calibrated edge from its raw measurement and the current
/// calibration values (Sa z Sb⁻¹, or U(K)).
void update_calibrated_measurements(PoseGraph& g);

/// g2o error of a calibrated edge: t2v(z⁻¹ (Xi Sa)⁻¹ (Xj Sb)) or t2v(U(K)⁻¹ Xi⁻¹ Xj).
Eigen::VectorXd calibrated_edge_error(const PoseGraph& g, const GraphEdge& e);

}  // namespace slamkit
