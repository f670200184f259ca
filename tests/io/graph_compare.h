// Test helpers for pose graphs: bit-exact and tolerant comparison, reading from text.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>

#include "slamkit/core/pose_graph.h"
#include "slamkit/io/pose_graph_io.h"

namespace slamkit::testing {

inline PoseGraph read_text(const std::string& text, const std::string& name = "test.g2o",
                           const PoseGraphReadOptions& options = {}, PoseGraphReadReport* report = nullptr) {
  std::istringstream in(text);
  return read_pose_graph(in, name, options, report);
}

/// |a − b| ≤ tol·max(1, |a|, |b|) elementwise; tol = 0 demands identical bits.
inline bool same(double a, double b, double tol) {
  if (tol == 0.0) return std::memcmp(&a, &b, sizeof(double)) == 0;
  return std::abs(a - b) <= tol * std::max({1.0, std::abs(a), std::abs(b)});
}

template <typename A, typename B>
::testing::AssertionResult same_matrix(const A& a, const B& b, double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return ::testing::AssertionFailure() << "size differs";
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index c = 0; c < a.cols(); ++c)
      if (!same(a(r, c), b(r, c), tol))
        return ::testing::AssertionFailure() << "(" << r << "," << c << "): " << a(r, c) << " vs " << b(r, c);
  return ::testing::AssertionSuccess();
}

/// |a − b| ≤ tol·max(1, max|a|) elementwise: rounding relative to the matrix, not the entry.
template <typename A, typename B>
::testing::AssertionResult same_matrix_scaled(const A& a, const B& b, double tol) {
  if (tol == 0.0) return same_matrix(a, b, 0.0);
  if (a.rows() != b.rows() || a.cols() != b.cols()) return ::testing::AssertionFailure() << "size differs";
  const double scale = std::max(1.0, a.cwiseAbs().maxCoeff());
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index c = 0; c < a.cols(); ++c)
      if (!(std::abs(a(r, c) - b(r, c)) <= tol * scale))
        return ::testing::AssertionFailure() << "(" << r << "," << c << "): " << a(r, c) << " vs " << b(r, c);
  return ::testing::AssertionSuccess();
}

/// Rotations compared as matrices (q and −q are the same rotation).
inline ::testing::AssertionResult same_pose3(const SE3& a, const SE3& b, double tol) {
  if (tol == 0.0) {
    auto r = same_matrix(a.rotation().quaternion().coeffs(), b.rotation().quaternion().coeffs(), 0.0);
    if (!r) return r;
  }
  auto r = same_matrix(a.rotation().matrix(), b.rotation().matrix(), tol);
  if (!r) return r;
  return same_matrix(a.translation(), b.translation(), tol);
}

/// Every element of a and b agrees: estimates and measurements to `pose_tol`, information to
/// `info_tol` relative to each matrix's largest entry (0 = identical bits). Returns the first
/// difference.
inline ::testing::AssertionResult same_graph(const PoseGraph& a, const PoseGraph& b, double pose_tol, double info_tol) {
  if (a.vertices().size() != b.vertices().size() || a.edges.size() != b.edges.size())
    return ::testing::AssertionFailure() << "sizes differ: " << a.vertices().size() << "/" << a.edges.size() << " vs "
                                         << b.vertices().size() << "/" << b.edges.size();
  for (std::size_t i = 0; i < a.vertices().size(); ++i) {
    const GraphVertex& u = a.vertices()[i];
    const GraphVertex& v = b.vertices()[i];
    if (u.id != v.id || u.kind != v.kind || u.has_estimate != v.has_estimate)
      return ::testing::AssertionFailure() << "vertex #" << i << " differs in id/kind/estimate flag";
    ::testing::AssertionResult r = ::testing::AssertionSuccess();
    switch (u.kind) {
      case VertexKind::kPose2:
        r = same_matrix(Eigen::Vector3d(u.pose2.x(), u.pose2.y(), u.pose2.theta()),
                        Eigen::Vector3d(v.pose2.x(), v.pose2.y(), v.pose2.theta()), pose_tol);
        break;
      case VertexKind::kPose3: r = same_pose3(u.pose3, v.pose3, pose_tol); break;
      default: r = same_matrix(u.point, v.point, pose_tol); break;
    }
    if (!r) return ::testing::AssertionFailure() << "vertex " << u.id << ": " << r.message();
  }
  for (std::size_t k = 0; k < a.edges.size(); ++k) {
    const GraphEdge& e = a.edges[k];
    const GraphEdge& f = b.edges[k];
    if (e.from != f.from || e.to != f.to || e.kind != f.kind || e.sensor_offset_id != f.sensor_offset_id)
      return ::testing::AssertionFailure() << "edge #" << k << " differs in ids/kind";
    ::testing::AssertionResult r = ::testing::AssertionSuccess();
    switch (e.kind) {
      case EdgeKind::kPose2Pose2:
        r = same_matrix(Eigen::Vector3d(e.pose2.x(), e.pose2.y(), e.pose2.theta()),
                        Eigen::Vector3d(f.pose2.x(), f.pose2.y(), f.pose2.theta()), pose_tol);
        break;
      case EdgeKind::kPose3Pose3: r = same_pose3(e.pose3, f.pose3, pose_tol); break;
      default: r = same_matrix(e.point, f.point, pose_tol); break;
    }
    if (!r) return ::testing::AssertionFailure() << "edge #" << k << " measurement: " << r.message();
    r = same_matrix_scaled(e.information, f.information, info_tol);
    if (!r) return ::testing::AssertionFailure() << "edge #" << k << " information: " << r.message();
  }
  if (a.fixed != b.fixed) return ::testing::AssertionFailure() << "fixed vertices differ";
  if (a.equivalences != b.equivalences) return ::testing::AssertionFailure() << "equivalences differ";
  if (a.sensor_offsets.size() != b.sensor_offsets.size()) return ::testing::AssertionFailure() << "offsets differ";
  for (const auto& [id, T] : a.sensor_offsets) {
    const auto it = b.sensor_offsets.find(id);
    if (it == b.sensor_offsets.end()) return ::testing::AssertionFailure() << "offset " << id << " missing";
    auto r = same_pose3(T, it->second, pose_tol);
    if (!r) return ::testing::AssertionFailure() << "offset " << id << ": " << r.message();
  }
  return ::testing::AssertionSuccess();
}

}  // namespace slamkit::testing
