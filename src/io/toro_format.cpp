// TORO graph format.
//
//   VERTEX2 id x y θ
//   EDGE2 i j dx dy dθ  I11 I12 I22 I33 I13 I23     (note the order)
//   EQUIV a b                                      (a and b are the same pose)
//   VERTEX3 / EDGE3                                (3D: the GTSAM EDGE3 text, gtsam_format.cpp)
//
// TORO's EDGE2 information belongs to a translation residual expressed in the frame of
// pose i; it is converted to g2o's with Ω_g2o = Tᵀ Ω_toro T, T = diag(R(dθ), 1)
// (information_conventions.h). TORO has no FIX tag and no landmarks.
#include <string>

#include "pose_graph_format.h"
#include "slamkit/core/error.h"
#include "slamkit/io/information_conventions.h"

namespace slamkit::io_detail {

void read_toro2d_record(const TextReader& r, GraphBuilder& b) {
  const std::string_view tag = r.field(0);
  if (tag == "VERTEX2") {
    expect_record(r, {"id", "x", "y", "theta"}, 0);
    b.require_dimension(r, 2);
    GraphVertex v;
    v.id = read_id(r, 1, "id");
    v.kind = VertexKind::kPose2;
    v.pose2 = SE2(r.number(2, "x"), r.number(3, "y"), r.number(4, "theta"));
    b.add_vertex(r, std::move(v));
  } else if (tag == "EDGE2") {
    expect_record(r, {"from", "to", "dx", "dy", "dtheta", "I11", "I12", "I22", "I33", "I13", "I23"}, 0);
    b.require_dimension(r, 2);
    GraphEdge e;
    e.from = read_id(r, 1, "from");
    e.to = read_id(r, 2, "to");
    e.kind = EdgeKind::kPose2Pose2;
    const double dtheta = r.number(5, "dtheta");
    e.pose2 = SE2(r.number(3, "dx"), r.number(4, "dy"), dtheta);
    const double i11 = r.number(6, "I11"), i12 = r.number(7, "I12"), i22 = r.number(8, "I22");
    const double i33 = r.number(9, "I33"), i13 = r.number(10, "I13"), i23 = r.number(11, "I23");
    Eigen::Matrix3d omega_toro;
    omega_toro << i11, i12, i13, i12, i22, i23, i13, i23, i33;
    e.information = toro2d_to_g2o_information(omega_toro, e.pose2.theta());
    require_finite_information(r, e.information);
    b.add_edge(r, std::move(e));
  } else if (tag == "EQUIV") {
    expect_record(r, {"a", "b"}, 0);
    b.add_equivalence(r, read_id(r, 1, "a"), read_id(r, 2, "b"));
  } else {
    r.fail("tag", "not a TORO 2D tag: '" + std::string(tag) + "'");  // the caller filters tags first
  }
}

void write_toro(const PoseGraph& g, std::string& out, std::vector<std::string>* warnings) {
  if (g.dimension() == 3) {
    write_edge3_records(g, out, "TORO");
  } else {
    for (const GraphVertex& v : g.vertices()) {
      if (v.kind != VertexKind::kPose2)
        throw InputError(g.source, v.line, "", std::string("TORO has no tag for ") + to_string(v.kind) + " vertices");
    }
    for (const GraphEdge& e : g.edges) {
      if (e.kind != EdgeKind::kPose2Pose2)
        throw InputError(g.source, e.line, "", std::string("TORO has no tag for ") + to_string(e.kind) + " edges");
    }
    if (vertices_to_write(g, "TORO")) {
      for (const GraphVertex& v : g.vertices()) {
        out += "VERTEX2 ";
        append_integer(out, v.id);
        append_numbers(out, {v.pose2.x(), v.pose2.y(), v.pose2.theta()});
        out += '\n';
      }
    }
    for (const GraphEdge& e : g.edges) {
      const Eigen::Matrix3d w = g2o_to_toro2d_information(e.information, e.pose2.theta());
      if (!w.allFinite())
        throw InputError(g.source, e.line, "information", "information overflows in TORO's convention");
      out += "EDGE2 ";
      append_integer(out, e.from);
      out += ' ';
      append_integer(out, e.to);
      append_numbers(out, {e.pose2.x(), e.pose2.y(), e.pose2.theta()});
      append_numbers(out, {w(0, 0), w(0, 1), w(1, 1), w(2, 2), w(0, 2), w(1, 2)});
      out += '\n';
    }
  }
  for (const auto& [a, b] : g.equivalences) {
    out += "EQUIV ";
    append_integer(out, a);
    out += ' ';
    append_integer(out, b);
    out += '\n';
  }
  if (warnings && !g.fixed.empty())
    warnings->push_back("TORO has no FIX tag: " + std::to_string(g.fixed.size()) + " fixed vertices dropped");
}

}  // namespace slamkit::io_detail
