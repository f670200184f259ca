// g2o calibration tags (types sclam2d, slam2d and slam3d offset edges, as g2o reads and
// writes them), plus two slamkit extensions for the linear odometry model:
//
//   PARAMS_SE2OFFSET id x y θ                         a constant in g2o (estimated on request)
//   EDGE_SE2_OFFSET i j pa pb dx dy dθ Ω(3×3)          z ≈ (Xi Pa)⁻¹ (Xj Pb)
//   EDGE_SE3_OFFSET i j pa pb x y z qx qy qz qw Ω(6×6) z ≈ (Xi Pa)⁻¹ (Xj Pb), PARAMS_SE3OFFSET
//   EDGE_SE2_CALIB i j s dx dy dθ Ω(3×3)               z ≈ (Xi S)⁻¹ (Xj S), S a VERTEX_SE2 (sclam2d)
//   VERTEX_ODOM_DIFFERENTIAL id k_l k_r b              sclam2d; g2o's default is 1 1 1
//   EDGE_SE2_ODOM_DIFFERENTIAL_CALIB i j k v_l v_r dt Ω(3×3)
//   EDGE_PRIOR_SE2 id x y θ Ω(3×3)                     accepted on sensor-offset vertices only
//   VERTEX_ODOM_LINEAR id K11 K12 … K33                slamkit: K (row-major) maps (Δx, Δy, Δθ)
//   EDGE_SE2_ODOM_LINEAR_CALIB i j k Δx Δy Δθ Ω(3×3)   slamkit
//   PRIOR_ODOM_DIFFERENTIAL id k_l k_r b Ω(3×3)        slamkit: prior on the odometry parameters
#include <algorithm>
#include <cmath>
#include <string>

#include "pose_graph_format.h"
#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_calibration.h"

namespace slamkit::io_detail {
namespace {

int read_param_id(const TextReader& r, std::size_t i, std::string_view name) {
  const std::int64_t id = r.integer(i, name);
  if (id < 0 || id > 0x7fffffff) r.fail(name, "parameter id out of range: " + std::to_string(id));
  return static_cast<int>(id);
}

GraphEdge calibrated_edge(const TextReader& r, EdgeKind kind, CalibratedEdgeKind ck, std::int64_t a, std::int64_t b) {
  GraphEdge e;
  e.from = read_id(r, 1, "from");
  e.to = read_id(r, 2, "to");
  e.kind = kind;
  CalibratedMeasurement c;
  c.kind = ck;
  c.param_a = a;
  c.param_b = b;
  e.calibrated = c;
  return e;
}

SE2 read_se2(const TextReader& r, std::size_t i, const char* x, const char* y, const char* t) {
  return SE2(r.number(i, x), r.number(i + 1, y), r.number(i + 2, t));
}

}  // namespace

bool is_g2o_calibration_tag(std::string_view tag) {
  static constexpr std::string_view kTags[] = {
      "PARAMS_SE2OFFSET", "EDGE_SE2_OFFSET",    "EDGE_SE3_OFFSET",           "EDGE_SE2_CALIB",
      "VERTEX_ODOM_DIFFERENTIAL", "EDGE_SE2_ODOM_DIFFERENTIAL_CALIB", "EDGE_PRIOR_SE2", "VERTEX_ODOM_LINEAR",
      "EDGE_SE2_ODOM_LINEAR_CALIB", "PRIOR_ODOM_DIFFERENTIAL"};
  return std::find(std::begin(kTags), std::end(kTags), tag) != std::end(kTags);
}

bool read_g2o_calibration_record(const TextReader& r, GraphBuilder& b) {
  const std::string_view tag = r.field(0);
  if (tag == "PARAMS_SE2OFFSET") {
    expect_record(r, {"id", "x", "y", "theta"}, 0);
    b.require_dimension(r, 2);
    b.add_offset_parameter2(r, read_param_id(r, 1, "id"), read_se2(r, 2, "x", "y", "theta"));
  } else if (tag == "EDGE_SE2_OFFSET") {
    expect_record(r, {"from", "to", "param_from", "param_to", "dx", "dy", "dtheta"}, 3);
    b.require_dimension(r, 2);
    GraphEdge e = calibrated_edge(r, EdgeKind::kPose2Pose2, CalibratedEdgeKind::kOffsetParams2,
                                  read_param_id(r, 3, "param_from"), read_param_id(r, 4, "param_to"));
    e.calibrated->sensor2 = read_se2(r, 5, "dx", "dy", "dtheta");
    e.information = read_upper_triangle(r, 8, 3);
    b.add_edge(r, std::move(e));
  } else if (tag == "EDGE_SE3_OFFSET") {
    expect_record(r, {"from", "to", "param_from", "param_to", "x", "y", "z", "qx", "qy", "qz", "qw"}, 6);
    b.require_dimension(r, 3);
    GraphEdge e = calibrated_edge(r, EdgeKind::kPose3Pose3, CalibratedEdgeKind::kOffsetParams3,
                                  read_param_id(r, 3, "param_from"), read_param_id(r, 4, "param_to"));
    const Eigen::Vector3d t(r.number(5, "x"), r.number(6, "y"), r.number(7, "z"));
    e.calibrated->sensor3 = SE3(read_quaternion(r, 8), t);
    e.information = read_upper_triangle(r, 12, 6);
    b.add_edge(r, std::move(e));
  } else if (tag == "EDGE_SE2_CALIB") {
    expect_record(r, {"from", "to", "offset_id", "dx", "dy", "dtheta"}, 3);
    b.require_dimension(r, 2);
    const std::int64_t s = read_id(r, 3, "offset_id");
    GraphEdge e = calibrated_edge(r, EdgeKind::kPose2Pose2, CalibratedEdgeKind::kSensorOffset2, s, s);
    e.calibrated->sensor2 = read_se2(r, 4, "dx", "dy", "dtheta");
    e.information = read_upper_triangle(r, 7, 3);
    b.add_edge(r, std::move(e));
  } else if (tag == "VERTEX_ODOM_DIFFERENTIAL") {
    expect_record(r, {"id", "k_left", "k_right", "baseline"}, 0);
    b.require_dimension(r, 2);
    CalibrationVertex v;
    v.id = read_id(r, 1, "id");
    v.kind = CalibrationKind::kOdomDifferential;
    v.value = Eigen::Vector3d(r.number(2, "k_left"), r.number(3, "k_right"), r.number(4, "baseline"));
    if (v.value[2] == 0.0) r.fail("baseline", "the wheel baseline must be non-zero");
    b.add_calibration_vertex(r, std::move(v));
  } else if (tag == "EDGE_SE2_ODOM_DIFFERENTIAL_CALIB") {
    expect_record(r, {"from", "to", "odometry_id", "v_left", "v_right", "dt"}, 3);
    b.require_dimension(r, 2);
    const std::int64_t k = read_id(r, 3, "odometry_id");
    GraphEdge e = calibrated_edge(r, EdgeKind::kPose2Pose2, CalibratedEdgeKind::kOdomDifferential, k, k);
    e.calibrated->odometry = Eigen::Vector3d(r.number(4, "v_left"), r.number(5, "v_right"), r.number(6, "dt"));
    e.information = read_upper_triangle(r, 7, 3);
    b.add_edge(r, std::move(e));
  } else if (tag == "VERTEX_ODOM_LINEAR") {
    expect_record(r, {"id", "K11", "K12", "K13", "K21", "K22", "K23", "K31", "K32", "K33"}, 0);
    b.require_dimension(r, 2);
    static constexpr const char* kNames[] = {"K11", "K12", "K13", "K21", "K22", "K23", "K31", "K32", "K33"};
    CalibrationVertex v;
    v.id = read_id(r, 1, "id");
    v.kind = CalibrationKind::kOdomLinear;
    v.value.resize(9);
    for (int k = 0; k < 9; ++k) v.value[k] = r.number(2 + static_cast<std::size_t>(k), kNames[k]);
    b.add_calibration_vertex(r, std::move(v));
  } else if (tag == "EDGE_SE2_ODOM_LINEAR_CALIB") {
    expect_record(r, {"from", "to", "odometry_id", "dx", "dy", "dtheta"}, 3);
    b.require_dimension(r, 2);
    const std::int64_t k = read_id(r, 3, "odometry_id");
    GraphEdge e = calibrated_edge(r, EdgeKind::kPose2Pose2, CalibratedEdgeKind::kOdomLinear, k, k);
    e.calibrated->odometry = Eigen::Vector3d(r.number(4, "dx"), r.number(5, "dy"), r.number(6, "dtheta"));
    e.information = read_upper_triangle(r, 7, 3);
    b.add_edge(r, std::move(e));
  } else if (tag == "EDGE_PRIOR_SE2" || tag == "PRIOR_ODOM_DIFFERENTIAL") {
    const bool offset = tag == "EDGE_PRIOR_SE2";
    if (offset) expect_record(r, {"id", "x", "y", "theta"}, 3);
    else expect_record(r, {"id", "k_left", "k_right", "baseline"}, 3);
    b.require_dimension(r, 2);
    CalibrationPrior p;
    p.id = read_id(r, 1, "id");
    p.mean = offset ? Eigen::Vector3d(r.number(2, "x"), r.number(3, "y"), r.number(4, "theta"))
                    : Eigen::Vector3d(r.number(2, "k_left"), r.number(3, "k_right"), r.number(4, "baseline"));
    p.information = read_upper_triangle(r, 5, 3);
    b.add_calibration_prior(r, std::move(p));
  } else {
    return false;
  }
  return true;
}

void GraphBuilder::add_offset_parameter2(const TextReader& r, int id, const SE2& offset) {
  if (!g_.calibration.offset_parameters2.emplace(id, offset).second)
    r.fail("id", "duplicate parameter id " + std::to_string(id));
}

void GraphBuilder::add_calibration_vertex(const TextReader& r, CalibrationVertex v) {
  v.line = r.line_number();
  if (const CalibrationVertex* old = g_.calibration.find(v.id))
    r.fail("id", "duplicate vertex id " + std::to_string(v.id) + " (first defined on line " + std::to_string(old->line) + ")");
  if (g_.index_of(v.id))
    r.fail("id", "duplicate vertex id " + std::to_string(v.id) + " (first defined on line " +
                     std::to_string(g_.vertex(v.id).line) + ")");
  g_.calibration.vertices.push_back(std::move(v));
}

void GraphBuilder::add_calibration_prior(const TextReader& r, CalibrationPrior p) {
  p.line = r.line_number();
  g_.calibration.priors.push_back(std::move(p));
}

void GraphBuilder::resolve_calibration() {
  // Offsets named by EDGE_SE2_CALIB: their VERTEX_SE2 lines become calibration vertices.
  std::vector<std::int64_t> moved;
  for (const GraphEdge& e : g_.edges) {
    if (!e.calibrated || e.calibrated->kind != CalibratedEdgeKind::kSensorOffset2) continue;
    const std::int64_t s = e.calibrated->param_a;
    if (std::find(moved.begin(), moved.end(), s) != moved.end()) continue;
    const auto index = g_.index_of(s);
    if (!index || !g_.vertices()[*index].has_estimate) {
      throw InputError(g_.source, e.line, "offset_id",
                       "EDGE_SE2_CALIB names sensor offset " + std::to_string(s) + ", which has no VERTEX_SE2 line");
    }
    const GraphVertex& v = g_.vertices()[*index];
    if (v.kind != VertexKind::kPose2)
      throw InputError(g_.source, e.line, "offset_id", "sensor offset " + std::to_string(s) + " is not a VERTEX_SE2");
    CalibrationVertex c;
    c.id = s;
    c.kind = CalibrationKind::kOffset2;
    c.value = Eigen::Vector3d(v.pose2.x(), v.pose2.y(), v.pose2.theta());
    c.line = v.line;
    g_.calibration.vertices.push_back(c);
    moved.push_back(s);
  }
  g_.remove_vertices(moved);
  std::sort(g_.calibration.vertices.begin(), g_.calibration.vertices.end(),
            [](const CalibrationVertex& a, const CalibrationVertex& b) { return a.id < b.id; });  // writers keep id order
  // No calibration vertex may be a pose endpoint.
  for (const GraphEdge& e : g_.edges) {
    for (const auto& [id, field] : {std::pair{e.from, "from"}, std::pair{e.to, "to"}}) {
      if (const CalibrationVertex* c = g_.calibration.find(id))
        throw InputError(g_.source, e.line, field,
                         "vertex " + std::to_string(id) + " is a calibration vertex (" + to_string(c->kind) +
                             ", line " + std::to_string(c->line) + "), not a pose");
    }
  }
  // FIX of a calibration vertex holds it at its value.
  for (auto it = references_.begin(); it != references_.end();) {
    CalibrationVertex* c = std::string(it->tag) == "FIX" ? g_.calibration.find(it->id) : nullptr;
    if (!c) {
      ++it;
      continue;
    }
    c->estimate = false;
    g_.fixed.erase(std::remove(g_.fixed.begin(), g_.fixed.end(), it->id), g_.fixed.end());
    it = references_.erase(it);
  }
  // Every calibrated edge names parameters of the right kind.
  for (const GraphEdge& e : g_.edges) {
    if (!e.calibrated) continue;
    const CalibratedMeasurement& c = *e.calibrated;
    auto need_vertex = [&](CalibrationKind kind, const char* field) {
      const CalibrationVertex* v = g_.calibration.find(c.param_a);
      if (!v || v->kind != kind)
        throw InputError(g_.source, e.line, field,
                         std::string(to_string(c.kind)) + " needs a " + to_string(kind) + " vertex, " +
                             std::to_string(c.param_a) + (v ? " is " + std::string(to_string(v->kind)) : " does not exist"));
    };
    switch (c.kind) {
      case CalibratedEdgeKind::kSensorOffset2: need_vertex(CalibrationKind::kOffset2, "offset_id"); break;
      case CalibratedEdgeKind::kOdomDifferential: need_vertex(CalibrationKind::kOdomDifferential, "odometry_id"); break;
      case CalibratedEdgeKind::kOdomLinear: need_vertex(CalibrationKind::kOdomLinear, "odometry_id"); break;
      case CalibratedEdgeKind::kOffsetParams2:
      case CalibratedEdgeKind::kOffsetParams3: {
        const bool two = c.kind == CalibratedEdgeKind::kOffsetParams2;
        for (const auto& [id, field] : {std::pair{c.param_a, "param_from"}, std::pair{c.param_b, "param_to"}}) {
          const bool known = two ? g_.calibration.offset_parameters2.count(static_cast<int>(id)) > 0
                                 : g_.sensor_offsets.count(static_cast<int>(id)) > 0;
          if (!known)
            throw InputError(g_.source, e.line, field,
                             std::string("no ") + (two ? "PARAMS_SE2OFFSET" : "PARAMS_SE3OFFSET") + " with id " +
                                 std::to_string(id));
        }
        break;
      }
    }
  }
  for (const CalibrationPrior& p : g_.calibration.priors) {
    const CalibrationVertex* v = g_.calibration.find(p.id);
    if (!v || (v->kind != CalibrationKind::kOffset2 && v->kind != CalibrationKind::kOdomDifferential))
      throw InputError(g_.source, p.line, "id",
                       "prior on vertex " + std::to_string(p.id) +
                           ": slamkit reads priors on sensor-offset and differential-odometry vertices only");
  }
  update_calibrated_measurements(g_);
  for (const GraphEdge& e : g_.edges) {
    if (!e.calibrated) continue;
    const bool finite = e.kind == EdgeKind::kPose2Pose2
                            ? e.pose2.translation().allFinite() && std::isfinite(e.pose2.theta())
                            : e.pose3.translation().allFinite() && e.pose3.rotation().quaternion().coeffs().allFinite();
    if (!finite)
      throw InputError(g_.source, e.line, "measurement",
                       std::string(to_string(e.calibrated->kind)) + ": the calibrated motion overflows");
  }
}

namespace {

void append_se2(std::string& out, const SE2& s) { append_numbers(out, {s.x(), s.y(), s.theta()}); }

}  // namespace

void write_g2o_calibration_section(const PoseGraph& g, std::string& out) {
  for (const auto& [id, s] : g.calibration.offset_parameters2) {
    out += "PARAMS_SE2OFFSET ";
    append_integer(out, id);
    append_se2(out, s);
    out += '\n';
  }
  for (const CalibrationVertex& v : g.calibration.vertices) {
    static constexpr const char* kTags[] = {"VERTEX_SE2 ", "VERTEX_ODOM_DIFFERENTIAL ", "VERTEX_ODOM_LINEAR "};
    out += kTags[static_cast<int>(v.kind)];
    append_integer(out, v.id);
    for (Eigen::Index k = 0; k < v.value.size(); ++k) {
      out += ' ';
      append_number(out, v.value[k]);
    }
    out += '\n';
  }
  for (const CalibrationVertex& v : g.calibration.vertices) {
    if (v.estimate) continue;
    out += "FIX ";
    append_integer(out, v.id);
    out += '\n';
  }
  for (const CalibrationPrior& p : g.calibration.priors) {
    const CalibrationVertex* v = g.calibration.find(p.id);
    out += v && v->kind == CalibrationKind::kOffset2 ? "EDGE_PRIOR_SE2 " : "PRIOR_ODOM_DIFFERENTIAL ";
    append_integer(out, p.id);
    append_numbers(out, {p.mean[0], p.mean[1], p.mean[2]});
    append_upper_triangle(out, p.information);
    out += '\n';
  }
}

void append_g2o_calibrated_edge(std::string& out, const GraphEdge& e) {
  const CalibratedMeasurement& c = *e.calibrated;
  out += to_string(c.kind);
  out += ' ';
  append_integer(out, e.from);
  out += ' ';
  append_integer(out, e.to);
  out += ' ';
  append_integer(out, c.param_a);
  switch (c.kind) {
    case CalibratedEdgeKind::kOffsetParams2:
      out += ' ';
      append_integer(out, c.param_b);
      append_se2(out, c.sensor2);
      break;
    case CalibratedEdgeKind::kOffsetParams3: {
      out += ' ';
      append_integer(out, c.param_b);
      const Eigen::Vector3d& t = c.sensor3.translation();
      const Eigen::Quaterniond& q = c.sensor3.rotation().quaternion();
      append_numbers(out, {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()});
      break;
    }
    case CalibratedEdgeKind::kSensorOffset2: append_se2(out, c.sensor2); break;
    case CalibratedEdgeKind::kOdomDifferential:
    case CalibratedEdgeKind::kOdomLinear: append_numbers(out, {c.odometry[0], c.odometry[1], c.odometry[2]}); break;
  }
  append_upper_triangle(out, e.information);
  out += '\n';
}

}  // namespace slamkit::io_detail
