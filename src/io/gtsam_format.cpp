// GTSAM EDGE3 text (identical to TORO 3D):
//
//   VERTEX3 id x y z roll pitch yaw
//   EDGE3 i j x y z roll pitch yaw  Ω(6×6 upper, order x y z roll pitch yaw)
//
// R = Rz(yaw)·Ry(pitch)·Rx(roll). Ω's rotation part belongs to the rotation vector of the
// error, not to the angles; it is converted to g2o's [t; q.vec] with ×4 / ×2
// (information_conventions.h).
#include <cmath>
#include <string>

#include "pose_graph_format.h"
#include "slamkit/core/error.h"
#include "slamkit/io/information_conventions.h"

namespace slamkit::io_detail {

namespace {

SE3 read_pose_rpy(const TextReader& r, std::size_t i) {
  const Eigen::Vector3d t(r.number(i, "x"), r.number(i + 1, "y"), r.number(i + 2, "z"));
  const double roll = r.number(i + 3, "roll"), pitch = r.number(i + 4, "pitch"), yaw = r.number(i + 5, "yaw");
  return SE3(SO3::from_rpy(roll, pitch, yaw), t);
}

void append_pose_rpy(std::string& out, const SE3& T) {
  const Eigen::Vector3d& t = T.translation();
  const Eigen::Vector3d rpy = T.rotation().to_rpy();
  append_numbers(out, {t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z()});
}

}  // namespace

void read_edge3_record(const TextReader& r, GraphBuilder& b) {
  const std::string_view tag = r.field(0);
  if (tag == "VERTEX3") {
    expect_record(r, {"id", "x", "y", "z", "roll", "pitch", "yaw"}, 0);
    b.require_dimension(r, 3);
    GraphVertex v;
    v.id = read_id(r, 1, "id");
    v.kind = VertexKind::kPose3;
    v.pose3 = read_pose_rpy(r, 2);
    b.add_vertex(r, std::move(v));
  } else if (tag == "EDGE3") {
    expect_record(r, {"from", "to", "x", "y", "z", "roll", "pitch", "yaw"}, 6);
    b.require_dimension(r, 3);
    GraphEdge e;
    e.from = read_id(r, 1, "from");
    e.to = read_id(r, 2, "to");
    e.kind = EdgeKind::kPose3Pose3;
    e.pose3 = read_pose_rpy(r, 3);
    e.information = rotation_vector_to_g2o_information(read_upper_triangle(r, 9, 6));
    require_finite_information(r, e.information);
    b.add_edge(r, std::move(e));
  } else {
    r.fail("tag", "not a VERTEX3/EDGE3 tag: '" + std::string(tag) + "'");  // the caller filters tags first
  }
}

void write_edge3_records(const PoseGraph& g, std::string& out, const char* format) {
  for (const GraphVertex& v : g.vertices()) {
    if (v.kind != VertexKind::kPose3)
      throw InputError(g.source, v.line, "", std::string(format) + " 3D has no tag for " + to_string(v.kind) + " vertices");
  }
  for (const GraphEdge& e : g.edges) {
    if (e.kind != EdgeKind::kPose3Pose3)
      throw InputError(g.source, e.line, "", std::string(format) + " 3D has no tag for " + to_string(e.kind) + " edges");
  }
  if (vertices_to_write(g, format)) {
    for (const GraphVertex& v : g.vertices()) {
      out += "VERTEX3 ";
      append_integer(out, v.id);
      append_pose_rpy(out, v.pose3);
      out += '\n';
    }
  }
  for (const GraphEdge& e : g.edges) {
    out += "EDGE3 ";
    append_integer(out, e.from);
    out += ' ';
    append_integer(out, e.to);
    append_pose_rpy(out, e.pose3);
    append_upper_triangle(out, g2o_to_rotation_vector_information(e.information));
    out += '\n';
  }
}

void write_gtsam(const PoseGraph& g, std::string& out, std::vector<std::string>* warnings) {
  const int dimension = g.dimension();
  if (dimension == 2) {
    throw InputError(g.source, 0, "",
                     "GTSAM EDGE3 text holds 3D pose graphs only; this graph is 2D (write g2o or TORO instead)");
  }
  write_edge3_records(g, out, "GTSAM");
  if (warnings && !g.fixed.empty())
    warnings->push_back("GTSAM EDGE3 text has no FIX tag: " + std::to_string(g.fixed.size()) + " fixed vertices dropped");
  if (warnings && !g.equivalences.empty()) {
    warnings->push_back("GTSAM EDGE3 text has no EQUIV tag: " + std::to_string(g.equivalences.size()) +
                        " vertex equivalences dropped");
  }
}

}  // namespace slamkit::io_detail
