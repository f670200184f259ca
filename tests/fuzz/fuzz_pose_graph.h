// Shared libFuzzer harness for the pose-graph readers.
//
// Feeds the bytes to the stream reader of one format. InputError is the expected outcome of
// bad input; any other exception escapes to libFuzzer (reported as a crash), and so do
// sanitizer reports. An accepted graph must also survive everything downstream: chi2,
// components, information health, and a write → read round trip that reproduces it
// (bit-identical for g2o, to rounding for TORO/GTSAM whose rotations pass through sin/cos).
// Byte 0 also selects options (unknown tags as warnings, repair, odometry completion).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/core/information.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"

namespace slamkit::fuzz {

[[noreturn]] inline void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// |a − b| ≤ tol · scale, or both identical.
inline bool close(double a, double b, double scale, double tol) {
  return same_bits(a, b) || std::abs(a - b) <= tol * std::max(1.0, scale);
}

template <typename M>
bool same_matrix(const M& a, const M& b, double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  const double scale = a.cwiseAbs().maxCoeff();
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index c = 0; c < a.cols(); ++c)
      if (!(tol == 0.0 ? same_bits(a(r, c), b(r, c)) : close(a(r, c), b(r, c), scale, tol))) return false;
  return true;
}

inline void check_same(const PoseGraph& a, const PoseGraph& b, double tol) {
  if (a.vertices().size() != b.vertices().size() || a.edges.size() != b.edges.size()) violation("sizes differ");
  for (std::size_t i = 0; i < a.vertices().size(); ++i) {
    const GraphVertex& u = a.vertices()[i];
    const GraphVertex& v = b.vertices()[i];
    if (u.id != v.id || u.kind != v.kind) violation("vertex ids/kinds differ");
    if (!same_matrix(u.point, v.point, tol) || !same_matrix(u.pose3.translation(), v.pose3.translation(), tol) ||
        !same_matrix(u.pose2.translation(), v.pose2.translation(), tol) ||
        !same_matrix(u.pose3.rotation().matrix(), v.pose3.rotation().matrix(), tol) ||
        !same_matrix(u.pose2.rotation().matrix(), v.pose2.rotation().matrix(), tol))
      violation("vertex estimates differ");
  }
  for (std::size_t k = 0; k < a.edges.size(); ++k) {
    const GraphEdge& e = a.edges[k];
    const GraphEdge& f = b.edges[k];
    if (e.from != f.from || e.to != f.to || e.kind != f.kind || e.sensor_offset_id != f.sensor_offset_id)
      violation("edge ids/kinds differ");
    if (!same_matrix(e.point, f.point, tol) || !same_matrix(e.pose3.translation(), f.pose3.translation(), tol) ||
        !same_matrix(e.pose2.translation(), f.pose2.translation(), tol) ||
        !same_matrix(e.pose3.rotation().matrix(), f.pose3.rotation().matrix(), tol) ||
        !same_matrix(e.pose2.rotation().matrix(), f.pose2.rotation().matrix(), tol))
      violation("edge measurements differ");
    if (!same_matrix(e.information, f.information, tol)) violation("edge information differs");
  }
}

inline int fuzz_pose_graph(const std::uint8_t* data, std::size_t size, PoseGraphFormat format, const char* name) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::uint8_t flags = size > 0 ? data[0] : 0;
  PoseGraphReadOptions options;
  options.format = (flags & 8) ? PoseGraphFormat::kAuto : format;
  options.unknown_tags_as_warnings = flags & 1;
  options.repair_information = flags & 2;
  options.complete_estimates = !(flags & 4);
  PoseGraph g;
  PoseGraphReadReport report;
  try {
    std::istringstream in(text);
    g = read_pose_graph(in, name, options, &report);
  } catch (const InputError& e) {
    if (e.file() != name) violation("an InputError that does not name the input");
    return 0;  // rejected with file, line and field: the expected outcome
  }
  // Downstream consumers must cope with any accepted graph.
  (void)total_chi2(g);
  (void)count_connected_components(g);
  (void)check_information(g);
  if (g.dimension() != 0 && g.dimension() != 2 && g.dimension() != 3) violation("dimension");

  std::string written;
  try {
    written = pose_graph_to_string(g, report.format);
  } catch (const InputError&) {
    return 0;  // e.g. an information matrix that overflows in TORO's convention
  }
  PoseGraphReadOptions again;
  again.format = report.format;
  again.complete_estimates = options.complete_estimates;
  PoseGraph h;
  try {
    std::istringstream in(written);
    h = read_pose_graph(in, name, again);
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading the written graph failed: %s\n", e.what());
    violation("write -> read");
  }
  check_same(g, h, report.format == PoseGraphFormat::kG2o ? 0.0 : 1e-9);
  return 0;
}

}  // namespace slamkit::fuzz
