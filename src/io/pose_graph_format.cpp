#include "pose_graph_format.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "slamkit/core/error.h"
#include "slamkit/io/information_conventions.h"

namespace slamkit::io_detail {

// ---------------------------------------------------------------- GraphBuilder

void GraphBuilder::require_dimension(const TextReader& r, int dimension) {
  if (dimension_ == 0) {
    dimension_ = dimension;
    dimension_line_ = r.line_number();
  } else if (dimension_ != dimension) {
    r.fail("tag", "a " + std::to_string(dimension) + "D record in a " + std::to_string(dimension_) +
                      "D file (first " + std::to_string(dimension_) + "D record on line " +
                      std::to_string(dimension_line_) + ")");
  }
}

void GraphBuilder::add_vertex(const TextReader& r, GraphVertex v) {
  has_vertex_lines_ = true;
  v.line = r.line_number();
  // Pose/point and calibration vertices share one id space (a fuzz finding: a pose vertex after a
  // calibration vertex of the same id was accepted, and the written file did not read back).
  if (const CalibrationVertex* old = g_.calibration.find(v.id))
    r.fail("id", "duplicate vertex id " + std::to_string(v.id) + " (first defined on line " + std::to_string(old->line) +
                     ")");
  if (!g_.add_vertex(v)) {
    r.fail("id", "duplicate vertex id " + std::to_string(v.id) + " (first defined on line " +
                     std::to_string(g_.vertex(v.id).line) + ")");
  }
}

void GraphBuilder::add_edge(const TextReader& r, GraphEdge e) {
  if (e.from == e.to) r.fail("to", "edge connects vertex " + std::to_string(e.from) + " to itself");
  e.line = r.line_number();
  g_.edges.push_back(std::move(e));
}

void GraphBuilder::add_fixed(const TextReader& r, std::int64_t id) {
  references_.push_back({id, r.line_number(), "id", "FIX"});
  if (std::find(g_.fixed.begin(), g_.fixed.end(), id) == g_.fixed.end()) g_.fixed.push_back(id);
}

void GraphBuilder::add_equivalence(const TextReader& r, std::int64_t a, std::int64_t b) {
  if (a == b) r.fail("b", "EQUIV of vertex " + std::to_string(a) + " with itself");
  references_.push_back({a, r.line_number(), "a", "EQUIV"});
  references_.push_back({b, r.line_number(), "b", "EQUIV"});
  g_.equivalences.emplace_back(a, b);
}

void GraphBuilder::add_sensor_offset(const TextReader& r, int id, const SE3& offset) {
  if (!g_.sensor_offsets.emplace(id, offset).second)
    r.fail("id", "duplicate parameter id " + std::to_string(id));
}

void GraphBuilder::warn(const TextReader& r, const std::string& message) {
  warnings_.push_back(r.source() + ":" + std::to_string(r.line_number()) + ": " + message);
}

namespace {

struct EndpointKinds {
  VertexKind from, to;
};

EndpointKinds endpoint_kinds(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kPose2Pose2: return {VertexKind::kPose2, VertexKind::kPose2};
    case EdgeKind::kPose3Pose3: return {VertexKind::kPose3, VertexKind::kPose3};
    case EdgeKind::kPose2Point2: return {VertexKind::kPose2, VertexKind::kPoint2};
    case EdgeKind::kPose3Point3: return {VertexKind::kPose3, VertexKind::kPoint3};
  }
  return {VertexKind::kPose2, VertexKind::kPose2};
}

}  // namespace

void GraphBuilder::check_reference(const Reference& ref) const {
  if (!g_.index_of(ref.id))
    throw InputError(g_.source, ref.line, ref.field, std::string(ref.tag) + " names unknown vertex " + std::to_string(ref.id));
}

void GraphBuilder::create_vertices_from_edges() {
  // Kind of each id from the first edge naming it; check_edge_kinds() reports conflicts.
  std::unordered_map<std::int64_t, VertexKind> kinds;
  kinds.reserve(2 * g_.edges.size());
  for (const GraphEdge& e : g_.edges) {
    const EndpointKinds k = endpoint_kinds(e.kind);
    kinds.emplace(e.from, k.from);
    kinds.emplace(e.to, k.to);
  }
  std::vector<std::pair<std::int64_t, VertexKind>> sorted(kinds.begin(), kinds.end());
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [id, kind] : sorted) {
    GraphVertex v;
    v.id = id;
    v.kind = kind;
    v.has_estimate = false;
    g_.add_vertex(v);
  }
}

void GraphBuilder::check_edge_kinds() const {
  for (const GraphEdge& e : g_.edges) {
    const EndpointKinds want = endpoint_kinds(e.kind);
    const std::int64_t ids[2] = {e.from, e.to};
    const VertexKind kinds[2] = {want.from, want.to};
    const char* fields[2] = {"from", "to"};
    for (int k = 0; k < 2; ++k) {
      const auto index = g_.index_of(ids[k]);
      if (!index) {
        throw InputError(g_.source, e.line, fields[k],
                         "edge names unknown vertex " + std::to_string(ids[k]) +
                             " (the file has vertex lines, so every edge endpoint must be one)");
      }
      const GraphVertex& v = g_.vertices()[*index];
      if (v.kind != kinds[k]) {
        std::string where = v.line > 0 ? " (line " + std::to_string(v.line) + ")" : " (named by an earlier edge)";
        throw InputError(g_.source, e.line, fields[k],
                         std::string("a ") + to_string(e.kind) + " edge needs a " + to_string(kinds[k]) +
                             " vertex, but vertex " + std::to_string(ids[k]) + " is " + to_string(v.kind) + where);
      }
    }
    if (e.kind == EdgeKind::kPose3Point3 && !g_.sensor_offsets.count(e.sensor_offset_id)) {
      throw InputError(g_.source, e.line, "param_id",
                       "no PARAMS_SE3OFFSET with id " + std::to_string(e.sensor_offset_id));
    }
  }
}

bool GraphBuilder::finish() {
  if (!has_vertex_lines_) create_vertices_from_edges();
  resolve_calibration();
  check_edge_kinds();
  for (const Reference& ref : references_) check_reference(ref);
  return !has_vertex_lines_;
}

// ---------------------------------------------------------------- field readers

std::int64_t read_id(const TextReader& r, std::size_t i, std::string_view name) {
  const std::int64_t id = r.integer(i, name);
  constexpr std::int64_t kMaxId = std::numeric_limits<std::int64_t>::max() - 1;
  if (id < 0 || id > kMaxId)
    r.fail(name, "vertex id must be in [0, " + std::to_string(kMaxId) + "], got " + std::string(r.field(i)));
  return id;
}

Eigen::Quaterniond exact_unit_quaternion(const Eigen::Quaterniond& q) {
  Eigen::Vector4d c = q.coeffs();  // (x, y, z, w): the very vector whose norm() SO3 divides by
  if (c.norm() == 1.0) return q;
  c /= c.cwiseAbs().maxCoeff();  // no overflow or underflow in the norm below
  c /= c.norm();
  // Nudge the largest component by single ulps until norm() is exactly 1.0: then SO3's own
  // normalization (q / norm()) is the identity and write → read reproduces every bit.
  for (int iteration = 0; iteration < 16; ++iteration) {
    const double n = c.norm();
    if (n == 1.0) break;
    Eigen::Index k = 0;
    c.cwiseAbs().maxCoeff(&k);
    const double toward = n > 1.0 ? 0.0 : (c[k] > 0.0 ? 2.0 : -2.0);
    c[k] = std::nextafter(c[k], toward);
  }
  return Eigen::Quaterniond(c[3], c[0], c[1], c[2]);
}

Eigen::Quaterniond read_quaternion(const TextReader& r, std::size_t i) {
  const Eigen::Quaterniond q(r.number(i + 3, "qw"), r.number(i, "qx"), r.number(i + 1, "qy"), r.number(i + 2, "qz"));
  const double largest = q.coeffs().cwiseAbs().maxCoeff();
  if (largest == 0.0) r.fail("quaternion", "zero quaternion cannot be normalized");
  const double norm = largest * (q.coeffs() / largest).norm();
  if (norm < 1e-6) {
    r.fail("quaternion", "quaternion norm " + std::to_string(norm) +
                             " is too small to normalize (expected a unit quaternion)");
  }
  return exact_unit_quaternion(q);
}

SE3 exact_unit_rotation(const SE3& T) {
  return SE3(exact_unit_quaternion(T.rotation().quaternion()), T.translation());
}

const char* information_field_name(int row, int col) {
  static constexpr const char* kNames[6][6] = {
      {"I11", "I12", "I13", "I14", "I15", "I16"}, {"I21", "I22", "I23", "I24", "I25", "I26"},
      {"I31", "I32", "I33", "I34", "I35", "I36"}, {"I41", "I42", "I43", "I44", "I45", "I46"},
      {"I51", "I52", "I53", "I54", "I55", "I56"}, {"I61", "I62", "I63", "I64", "I65", "I66"}};
  return kNames[row][col];
}

void expect_record(const TextReader& r, std::initializer_list<const char*> head, int info_dim) {
  const std::size_t want = 1 + head.size() + static_cast<std::size_t>(info_dim * (info_dim + 1) / 2);
  const std::size_t have = r.num_fields();
  if (have == want) return;
  const std::string counts = std::string(r.field(0)) + " needs " + std::to_string(want) +
                             " fields (tag included), line has " + std::to_string(have);
  if (have > want) r.fail("extra", "unexpected '" + std::string(r.field(want)).substr(0, 40) + "': " + counts);
  // Name the first missing field.
  std::size_t i = have - 1;  // index into head, then into the triangle
  if (i < head.size()) r.fail(head.begin()[i], "missing: " + counts);
  i -= head.size();
  for (int row = 0; row < info_dim; ++row) {
    for (int col = row; col < info_dim; ++col, --i) {
      if (i == 0) r.fail(information_field_name(row, col), "missing: " + counts);
    }
  }
  r.fail("", counts);
}

Eigen::MatrixXd read_upper_triangle(const TextReader& r, std::size_t i, int n) {
  double values[21];
  int k = 0;
  for (int row = 0; row < n; ++row)
    for (int col = row; col < n; ++col, ++k) values[k] = r.number(i + k, information_field_name(row, col));
  return symmetric_from_upper_triangle(values, n);
}

void require_finite_information(const TextReader& r, const Eigen::MatrixXd& omega) {
  if (!omega.allFinite())
    r.fail("information", "information matrix overflows when converted to g2o's convention");
}

// ---------------------------------------------------------------- number formatting

void append_number(std::string& out, double v) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof(buf), v);  // shortest round trip
  out.append(buf, result.ptr);
}

void append_integer(std::string& out, std::int64_t v) {
  char buf[24];
  const auto result = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, result.ptr);
}

void append_numbers(std::string& out, std::initializer_list<double> values) {
  for (double v : values) {
    out += ' ';
    append_number(out, v);
  }
}

void append_upper_triangle(std::string& out, const Eigen::MatrixXd& omega) {
  for (Eigen::Index row = 0; row < omega.rows(); ++row) {
    for (Eigen::Index col = row; col < omega.cols(); ++col) {
      out += ' ';
      append_number(out, omega(row, col));
    }
  }
}

void check_writable(const PoseGraph& g) {
  constexpr std::int64_t kMaxId = std::numeric_limits<std::int64_t>::max() - 1;
  auto fail = [&g](int line, const std::string& message) { throw InputError(g.source, line, "", "cannot write: " + message); };
  for (const GraphVertex& v : g.vertices()) {
    const std::string name = "vertex " + std::to_string(v.id);
    if (v.id < 0 || v.id > kMaxId) fail(v.line, name + ": id out of range");
    if (!v.has_estimate) continue;
    const bool finite = v.pose2.translation().allFinite() && std::isfinite(v.pose2.theta()) &&
                        v.pose3.translation().allFinite() && v.pose3.rotation().quaternion().coeffs().allFinite() &&
                        v.point.allFinite();
    if (!finite) fail(v.line, name + " has a non-finite estimate");
  }
  for (const GraphEdge& e : g.edges) {
    const std::string name = "edge " + std::to_string(e.from) + "-" + std::to_string(e.to);
    const int n = error_dim(e.kind);
    if (e.information.rows() != n || e.information.cols() != n) {
      fail(e.line, name + " has a " + std::to_string(e.information.rows()) + "x" +
                       std::to_string(e.information.cols()) + " information matrix, expected " + std::to_string(n) +
                       "x" + std::to_string(n));
    }
    const bool finite = e.pose2.translation().allFinite() && std::isfinite(e.pose2.theta()) &&
                        e.pose3.translation().allFinite() && e.pose3.rotation().quaternion().coeffs().allFinite() &&
                        e.point.allFinite() && e.information.allFinite();
    if (!finite) fail(e.line, name + " has non-finite values");
    if (e.from == e.to) fail(e.line, name + " connects a vertex to itself");
    const EndpointKinds want = endpoint_kinds(e.kind);
    const auto a = g.index_of(e.from), b = g.index_of(e.to);
    if (!a || !b) fail(e.line, name + " names a vertex the graph does not have");
    if (g.vertices()[*a].kind != want.from || g.vertices()[*b].kind != want.to)
      fail(e.line, name + ": a " + to_string(e.kind) + " edge between vertices of other kinds");
    if (e.kind == EdgeKind::kPose3Point3 && !g.sensor_offsets.count(e.sensor_offset_id))
      fail(e.line, name + " uses the unknown sensor offset " + std::to_string(e.sensor_offset_id));
  }
  for (std::int64_t id : g.fixed)
    if (!g.index_of(id)) fail(0, "FIX names unknown vertex " + std::to_string(id));
  for (const auto& [a, b] : g.equivalences)
    if (!g.index_of(a) || !g.index_of(b) || a == b) fail(0, "bad EQUIV " + std::to_string(a) + " " + std::to_string(b));
  for (const auto& [id, offset] : g.sensor_offsets)
    if (id < 0 || !offset.translation().allFinite() || !offset.rotation().quaternion().coeffs().allFinite())
      fail(0, "bad sensor offset " + std::to_string(id));
}

bool vertices_to_write(const PoseGraph& g, const char* format) {
  const auto& vs = g.vertices();
  const auto with = std::count_if(vs.begin(), vs.end(), [](const GraphVertex& v) { return v.has_estimate; });
  if (with == 0) return false;
  if (static_cast<std::size_t>(with) == vs.size()) return true;
  const auto it = std::find_if(vs.begin(), vs.end(), [](const GraphVertex& v) { return !v.has_estimate; });
  throw InputError(g.source, it->line, "",
                   std::string("cannot write ") + format + ": vertex " + std::to_string(it->id) +
                       " has no estimate while others have one");
}

// ---------------------------------------------------------------- tags

TagFamily classify_tag(std::string_view tag) {
  static constexpr std::string_view kG2o[] = {"VERTEX_SE2",      "EDGE_SE2",         "VERTEX_SE3:QUAT",
                                              "EDGE_SE3:QUAT",   "FIX",              "VERTEX_XY",
                                              "EDGE_SE2_XY",     "VERTEX_TRACKXYZ",  "EDGE_SE3_TRACKXYZ",
                                              "PARAMS_SE3OFFSET"};
  for (std::string_view t : kG2o)
    if (tag == t) return TagFamily::kG2o;
  if (is_g2o_calibration_tag(tag)) return TagFamily::kG2o;
  if (tag == "VERTEX2" || tag == "EDGE2" || tag == "EQUIV") return TagFamily::kToro2d;
  if (tag == "VERTEX3" || tag == "EDGE3") return TagFamily::kEdge3;
  return TagFamily::kUnknown;
}

}  // namespace slamkit::io_detail
