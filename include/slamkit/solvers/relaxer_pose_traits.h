// 2D/3D dispatch for the relaxers that work on the manifold directly (Gauss-Seidel
// relaxation, multi-level relaxation): pose type, measurement, g2o edge error with Jacobians
// selected by the tangent dimension D (3: SE(2), 6: SE(3)). Shared by solvers and HOG-Man.
#pragma once

#include <Eigen/Core>

#include "slamkit/core/pose_graph.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit::detail {

template <int D>
struct RelaxerPose;

template <>
struct RelaxerPose<3> {
  using Pose = SE2;
  using Vec = Eigen::Vector3d;
  using Mat = Eigen::Matrix3d;
  static Pose& pose(GraphVertex& v) { return v.pose2; }
  static const Pose& pose(const GraphVertex& v) { return v.pose2; }
  static const Pose& measurement(const GraphEdge& e) { return e.pose2; }
  static Pose& measurement_ref(GraphEdge& e) { return e.pose2; }
  static Vec error(const Pose& Z, const Pose& a, const Pose& b, Mat* Ja, Mat* Jb) {
    return pose2_edge_error(Z, a, b, Ja, Jb);
  }
};

template <>
struct RelaxerPose<6> {
  using Pose = SE3;
  using Vec = Vector6d;
  using Mat = Matrix6d;
  static Pose& pose(GraphVertex& v) { return v.pose3; }
  static const Pose& pose(const GraphVertex& v) { return v.pose3; }
  static const Pose& measurement(const GraphEdge& e) { return e.pose3; }
  static Pose& measurement_ref(GraphEdge& e) { return e.pose3; }
  static Vec error(const Pose& Z, const Pose& a, const Pose& b, Mat* Ja, Mat* Jb) {
    return pose3_edge_error(Z, a, b, Ja, Jb);
  }
};

}  // namespace slamkit::detail
