// PoseGraph: a pose-graph dataset as files describe it — vertices (2D/3D poses and
// landmarks) with initial estimates, edges with a measurement and an information matrix.
//
// This is the exchange type between io (readers/writers), the initializers and the
// optimizer front end, which turns it into a FactorGraph. Edge errors follow g2o
// (pose_graph_error.h); the information matrix is expressed in that error's coordinates:
//   pose2–pose2 (x, y, θ) · pose3–pose3 (x, y, z, qx, qy, qz) · pose–point (x, y[, z]).
// Invariant: vertex ids are unique; index_of() is O(1). Not thread-safe for writes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "slamkit/core/calibration.h"
#include "slamkit/core/trajectory.h"
#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

enum class VertexKind : std::uint8_t { kPose2, kPose3, kPoint2, kPoint3 };
enum class EdgeKind : std::uint8_t { kPose2Pose2, kPose3Pose3, kPose2Point2, kPose3Point3 };

const char* to_string(VertexKind kind);
const char* to_string(EdgeKind kind);
/// Tangent dimension of a vertex kind (3, 6, 2, 3).
int tangent_dim(VertexKind kind);
/// Dimension of an edge's error (3, 6, 2, 3).
int error_dim(EdgeKind kind);

struct GraphVertex {
  std::int64_t id = 0;
  VertexKind kind = VertexKind::kPose2;
  SE2 pose2;                                        ///< kPose2
  SE3 pose3;                                        ///< kPose3
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< kPoint2 (x, y, 0) and kPoint3
  bool has_estimate = true;  ///< false for vertices only named by edges (edges-only files)
  int line = 0;              ///< source line, 0 if not from a file
};

struct GraphEdge {
  std::int64_t from = 0;  ///< the pose the measurement is expressed in
  std::int64_t to = 0;
  EdgeKind kind = EdgeKind::kPose2Pose2;
  SE2 pose2;                                        ///< measurement, kPose2Pose2
  SE3 pose3;                                        ///< measurement, kPose3Pose3
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< measurement, pose–point edges
  Eigen::MatrixXd information;                      ///< error_dim × error_dim
  int sensor_offset_id = -1;  ///< EDGE_SE3_TRACKXYZ: the PARAMS_SE3OFFSET it uses
  /// Set for a pose–pose edge measured through calibration parameters (core/calibration.h);
  /// pose2/pose3 then hold the effective measurement at the current parameter values.
  std::optional<CalibratedMeasurement> calibrated;
  int line = 0;
};

class PoseGraph {
 public:
  std::string source = "<memory>";  ///< file the graph came from, for messages
  std::string format;               ///< "g2o", "toro", "gtsam" or empty
  std::vector<GraphEdge> edges;
  std::vector<std::int64_t> fixed;  ///< FIX: gauge vertices
  std::vector<std::pair<std::int64_t, std::int64_t>> equivalences;  ///< TORO EQUIV a b
  std::map<int, SE3> sensor_offsets;                                 ///< g2o PARAMS_SE3OFFSET
  CalibrationSection calibration;  ///< sensor-parameter variables (core/calibration.h)

  /// Adds a vertex; returns false (and changes nothing) if its id exists already.
  bool add_vertex(const GraphVertex& v);
  const std::vector<GraphVertex>& vertices() const { return vertices_; }
  /// Mutable access to estimates; ids and kinds must not be changed through it.
  GraphVertex& vertex_at(std::size_t index) { return vertices_[index]; }
  std::optional<std::size_t> index_of(std::int64_t id) const;
  /// Removes the vertices with these ids (e.g. VERTEX_SE2 lines that turn out to be sensor
  /// offsets); keeps the order of the others. O(V).
  void remove_vertices(const std::vector<std::int64_t>& ids);
  const GraphVertex& vertex(std::int64_t id) const;  ///< throws InputError if unknown

  /// 2 or 3 from the pose kinds; 0 for an empty graph. Throws if 2D and 3D poses are mixed.
  int dimension() const;
  std::size_t num_poses() const;
  std::size_t num_points() const;

 private:
  std::vector<GraphVertex> vertices_;
  std::unordered_map<std::int64_t, std::size_t> index_;
};

/// Pose–pose edge between consecutive ids (|to − from| = 1): an odometry edge.
bool is_odometry(const GraphEdge& e);

/// Number of connected components (vertices joined by edges; EQUIV joins too).
std::size_t count_connected_components(const PoseGraph& g);

/// The vertices held fixed to remove the gauge freedom: the FIX vertices, plus, for every
/// connected component without one, its smallest pose id. Appends a human-readable note for
/// each choice made (missing FIX, several components) to `notes` if given.
/// Throws InputError if a FIX names an unknown vertex.
std::vector<std::int64_t> gauge_vertices(const PoseGraph& g, std::vector<std::string>* notes = nullptr);

/// The pose vertices as a trajectory in id order, the id as the timestamp (pose graphs have no
/// times); 2D poses become SE(3) poses in the z = 0 plane. Landmarks are left out.
Trajectory to_trajectory(const PoseGraph& g);

/// Gives every vertex without an estimate one, by composing measurements outward from the
/// vertices that have one: first along the odometry chain, then breadth-first over all edges.
/// A component without any estimate is rooted at its smallest id, at the identity. Returns the
/// number of vertices initialized.
std::size_t complete_estimates_by_odometry(PoseGraph& g);

}  // namespace slamkit
