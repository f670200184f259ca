// g2o text format (types slam2d / slam3d as g2o writes them).
//
//   VERTEX_SE2 id x y θ                     EDGE_SE2 i j dx dy dθ  Ω(3×3 upper)
//   VERTEX_SE3:QUAT id x y z qx qy qz qw    EDGE_SE3:QUAT i j x y z qx qy qz qw  Ω(6×6 upper)
//   VERTEX_XY id x y                        EDGE_SE2_XY i j x y  Ω(2×2 upper)
//   VERTEX_TRACKXYZ id x y z                EDGE_SE3_TRACKXYZ i j param x y z  Ω(3×3 upper)
//   PARAMS_SE3OFFSET id x y z qx qy qz qw   FIX id [id ...]
// and the calibration tags of g2o_calibration_format.cpp.
// Ω is listed as its upper triangle row by row and is already in PoseGraph's convention.
#include <string>

#include "pose_graph_format.h"
#include "slamkit/core/error.h"

namespace slamkit::io_detail {

namespace {

GraphVertex make_vertex(std::int64_t id, VertexKind kind) {
  GraphVertex v;
  v.id = id;
  v.kind = kind;
  return v;
}

GraphEdge make_edge(const TextReader& r, EdgeKind kind) {
  GraphEdge e;
  e.from = read_id(r, 1, "from");
  e.to = read_id(r, 2, "to");
  e.kind = kind;
  return e;
}

SE3 read_pose3(const TextReader& r, std::size_t i) {
  const Eigen::Vector3d t(r.number(i, "x"), r.number(i + 1, "y"), r.number(i + 2, "z"));
  return SE3(read_quaternion(r, i + 3), t);
}

}  // namespace

void read_g2o_record(const TextReader& r, GraphBuilder& b) {
  const std::string_view tag = r.field(0);
  if (tag == "VERTEX_SE2") {
    expect_record(r, {"id", "x", "y", "theta"}, 0);
    b.require_dimension(r, 2);
    GraphVertex v = make_vertex(read_id(r, 1, "id"), VertexKind::kPose2);
    v.pose2 = SE2(r.number(2, "x"), r.number(3, "y"), r.number(4, "theta"));
    b.add_vertex(r, std::move(v));
  } else if (tag == "EDGE_SE2") {
    expect_record(r, {"from", "to", "dx", "dy", "dtheta"}, 3);
    b.require_dimension(r, 2);
    GraphEdge e = make_edge(r, EdgeKind::kPose2Pose2);
    e.pose2 = SE2(r.number(3, "dx"), r.number(4, "dy"), r.number(5, "dtheta"));
    e.information = read_upper_triangle(r, 6, 3);
    b.add_edge(r, std::move(e));
  } else if (tag == "VERTEX_SE3:QUAT") {
    expect_record(r, {"id", "x", "y", "z", "qx", "qy", "qz", "qw"}, 0);
    b.require_dimension(r, 3);
    GraphVertex v = make_vertex(read_id(r, 1, "id"), VertexKind::kPose3);
    v.pose3 = read_pose3(r, 2);
    b.add_vertex(r, std::move(v));
  } else if (tag == "EDGE_SE3:QUAT") {
    expect_record(r, {"from", "to", "x", "y", "z", "qx", "qy", "qz", "qw"}, 6);
    b.require_dimension(r, 3);
    GraphEdge e = make_edge(r, EdgeKind::kPose3Pose3);
    e.pose3 = read_pose3(r, 3);
    e.information = read_upper_triangle(r, 10, 6);
    b.add_edge(r, std::move(e));
  } else if (tag == "VERTEX_XY") {
    expect_record(r, {"id", "x", "y"}, 0);
    b.require_dimension(r, 2);
    GraphVertex v = make_vertex(read_id(r, 1, "id"), VertexKind::kPoint2);
    v.point = Eigen::Vector3d(r.number(2, "x"), r.number(3, "y"), 0.0);
    b.add_vertex(r, std::move(v));
  } else if (tag == "EDGE_SE2_XY") {
    expect_record(r, {"from", "to", "x", "y"}, 2);
    b.require_dimension(r, 2);
    GraphEdge e = make_edge(r, EdgeKind::kPose2Point2);
    e.point = Eigen::Vector3d(r.number(3, "x"), r.number(4, "y"), 0.0);
    e.information = read_upper_triangle(r, 5, 2);
    b.add_edge(r, std::move(e));
  } else if (tag == "VERTEX_TRACKXYZ") {
    expect_record(r, {"id", "x", "y", "z"}, 0);
    b.require_dimension(r, 3);
    GraphVertex v = make_vertex(read_id(r, 1, "id"), VertexKind::kPoint3);
    v.point = Eigen::Vector3d(r.number(2, "x"), r.number(3, "y"), r.number(4, "z"));
    b.add_vertex(r, std::move(v));
  } else if (tag == "EDGE_SE3_TRACKXYZ") {
    expect_record(r, {"from", "to", "param_id", "x", "y", "z"}, 3);
    b.require_dimension(r, 3);
    GraphEdge e = make_edge(r, EdgeKind::kPose3Point3);
    const std::int64_t param = r.integer(3, "param_id");
    if (param < 0 || param > 0x7fffffff) r.fail("param_id", "parameter id out of range: " + std::to_string(param));
    e.sensor_offset_id = static_cast<int>(param);
    e.point = Eigen::Vector3d(r.number(4, "x"), r.number(5, "y"), r.number(6, "z"));
    e.information = read_upper_triangle(r, 7, 3);
    b.add_edge(r, std::move(e));
  } else if (tag == "PARAMS_SE3OFFSET") {
    expect_record(r, {"id", "x", "y", "z", "qx", "qy", "qz", "qw"}, 0);
    b.require_dimension(r, 3);
    const std::int64_t id = r.integer(1, "id");
    if (id < 0 || id > 0x7fffffff) r.fail("id", "parameter id out of range: " + std::to_string(id));
    b.add_sensor_offset(r, static_cast<int>(id), read_pose3(r, 2));
  } else if (tag == "FIX") {
    if (r.num_fields() < 2) r.fail("id", "missing: FIX needs at least one vertex id");
    for (std::size_t i = 1; i < r.num_fields(); ++i) b.add_fixed(r, read_id(r, i, "id"));
  } else if (!read_g2o_calibration_record(r, b)) {
    r.fail("tag", "not a g2o tag: '" + std::string(tag) + "'");  // the caller filters tags first
  }
}

namespace {

void append_quaternion(std::string& out, const Eigen::Quaterniond& q) {
  append_numbers(out, {q.x(), q.y(), q.z(), q.w()});
}

void append_pose3(std::string& out, const SE3& T) {
  const Eigen::Vector3d& t = T.translation();
  append_numbers(out, {t.x(), t.y(), t.z()});
  append_quaternion(out, T.rotation().quaternion());
}

void append_vertex(std::string& out, const GraphVertex& v) {
  switch (v.kind) {
    case VertexKind::kPose2:
      out += "VERTEX_SE2 ";
      append_integer(out, v.id);
      append_numbers(out, {v.pose2.x(), v.pose2.y(), v.pose2.theta()});
      break;
    case VertexKind::kPose3:
      out += "VERTEX_SE3:QUAT ";
      append_integer(out, v.id);
      append_pose3(out, v.pose3);
      break;
    case VertexKind::kPoint2:
      out += "VERTEX_XY ";
      append_integer(out, v.id);
      append_numbers(out, {v.point.x(), v.point.y()});
      break;
    case VertexKind::kPoint3:
      out += "VERTEX_TRACKXYZ ";
      append_integer(out, v.id);
      append_numbers(out, {v.point.x(), v.point.y(), v.point.z()});
      break;
  }
  out += '\n';
}

void append_edge(std::string& out, const GraphEdge& e) {
  if (e.calibrated) return append_g2o_calibrated_edge(out, e);
  static constexpr const char* kTags[] = {"EDGE_SE2 ", "EDGE_SE3:QUAT ", "EDGE_SE2_XY ", "EDGE_SE3_TRACKXYZ "};
  out += kTags[static_cast<int>(e.kind)];
  append_integer(out, e.from);
  out += ' ';
  append_integer(out, e.to);
  switch (e.kind) {
    case EdgeKind::kPose2Pose2: append_numbers(out, {e.pose2.x(), e.pose2.y(), e.pose2.theta()}); break;
    case EdgeKind::kPose3Pose3: append_pose3(out, e.pose3); break;
    case EdgeKind::kPose2Point2: append_numbers(out, {e.point.x(), e.point.y()}); break;
    case EdgeKind::kPose3Point3:
      out += ' ';
      append_integer(out, e.sensor_offset_id);
      append_numbers(out, {e.point.x(), e.point.y(), e.point.z()});
      break;
  }
  append_upper_triangle(out, e.information);
  out += '\n';
}

}  // namespace

void write_g2o(const PoseGraph& g, std::string& out, std::vector<std::string>* warnings) {
  for (const auto& [id, offset] : g.sensor_offsets) {
    out += "PARAMS_SE3OFFSET ";
    append_integer(out, id);
    append_pose3(out, offset);
    out += '\n';
  }
  if (vertices_to_write(g, "g2o")) {
    for (const GraphVertex& v : g.vertices()) append_vertex(out, v);
  }
  write_g2o_calibration_section(g, out);
  for (std::int64_t id : g.fixed) {
    out += "FIX ";
    append_integer(out, id);
    out += '\n';
  }
  for (const GraphEdge& e : g.edges) append_edge(out, e);
  if (!g.equivalences.empty() && warnings) {
    warnings->push_back("g2o has no EQUIV tag: " + std::to_string(g.equivalences.size()) +
                        " vertex equivalences dropped");
  }
}

}  // namespace slamkit::io_detail
