// Trajectory: a time-ordered sequence of body poses T_world_body, the exchange type between
// estimators (optimizer, filters, VIO), the trajectory readers/writers in io, and eval.
//
// Each sample has a stamp in seconds (double) and, when the source had one, the exact
// integer stamp in nanoseconds (EuRoC/ASL files, plain decimal TUM stamps); stamp equals
// stamp_ns / 1e9 up to rounding. Readers parse stamps as evo/numpy do, so association
// decisions at the max_diff boundary agree with evo. Optional per-sample state: velocity of
// the body in the world frame and IMU biases (gyroscope, accelerometer, in the body/IMU
// frame), as in EuRoC state CSVs.
//
// Rotation matrices read from a file (KITTI) are rarely exactly orthonormal; T_world_body
// holds a rotation projected from the matrix, and source_rotation keeps the matrix as read,
// so that metrics computed on it agree with tools that use the raw matrices (evo) to the
// last digits. Code that changes T_world_body must reset or update source_rotation;
// rotation_matrix() reads it.
//
// Invariants: stamps are non-decreasing (equal stamps are allowed: real files have them);
// a trajectory without timestamps (KITTI) uses the sample index as stamp and reports
// has_timestamps() == false, so that evaluation matches such files by index.
// Header-only value type; not thread-safe for writes.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "slamkit/geometry/se3.h"

namespace slamkit {

/// IMU biases: b_g [rad/s] and b_a [m/s²], both in the IMU (body) frame.
struct ImuBias {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};

/// One sample of a trajectory.
struct TrajectorySample {
  double stamp = 0.0;                        ///< seconds (or the index, without timestamps)
  std::optional<std::int64_t> stamp_ns;      ///< exact source stamp in ns, when there was one
  SE3 T_world_body;                          ///< pose of the body in the world frame
  std::optional<Eigen::Vector3d> v_world;    ///< body velocity in the world frame [m/s]
  std::optional<ImuBias> bias;               ///< IMU biases
  std::optional<Eigen::Matrix3d> source_rotation;  ///< R_world_body exactly as read (KITTI), see above

  /// The rotation matrix of the sample: source_rotation if set, else from T_world_body.
  Eigen::Matrix3d rotation_matrix() const {
    return source_rotation ? *source_rotation : T_world_body.rotation().matrix();
  }
};

class Trajectory {
 public:
  Trajectory() = default;

  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  const TrajectorySample& operator[](std::size_t i) const { return samples_[i]; }
  TrajectorySample& operator[](std::size_t i) { return samples_[i]; }
  const TrajectorySample& at(std::size_t i) const { return samples_.at(i); }
  std::vector<TrajectorySample>::const_iterator begin() const { return samples_.begin(); }
  std::vector<TrajectorySample>::const_iterator end() const { return samples_.end(); }
  const std::vector<TrajectorySample>& samples() const { return samples_; }

  /// Appends a sample; throws std::invalid_argument if its stamp is not finite or goes back in time.
  void push_back(TrajectorySample s) {
    if (!std::isfinite(s.stamp)) throw std::invalid_argument("Trajectory: stamp is not finite");
    if (!samples_.empty() && s.stamp < samples_.back().stamp)
      throw std::invalid_argument("Trajectory: stamps must be non-decreasing");
    samples_.push_back(std::move(s));
  }
  void push_back(double stamp, const SE3& T_world_body) {
    TrajectorySample s;
    s.stamp = stamp;
    s.T_world_body = T_world_body;
    push_back(std::move(s));
  }
  /// Appends a sample with an exact nanosecond stamp (stamp = double(ns) / 1e9).
  void push_back_ns(std::int64_t stamp_ns, const SE3& T_world_body) {
    TrajectorySample s;
    s.stamp = static_cast<double>(stamp_ns) / 1e9;
    s.stamp_ns = stamp_ns;
    s.T_world_body = T_world_body;
    push_back(std::move(s));
  }
  void reserve(std::size_t n) { samples_.reserve(n); }
  void clear() { samples_.clear(); }

  /// False for sources without time (KITTI): stamps are then the sample indices.
  bool has_timestamps() const { return has_timestamps_; }
  void set_has_timestamps(bool v) { has_timestamps_ = v; }
  /// True if the trajectory is non-empty and every sample has an exact ns stamp.
  bool has_stamps_ns() const { return all_of([](const TrajectorySample& s) { return s.stamp_ns.has_value(); }); }
  bool has_velocities() const { return all_of([](const TrajectorySample& s) { return s.v_world.has_value(); }); }
  bool has_biases() const { return all_of([](const TrajectorySample& s) { return s.bias.has_value(); }); }

  std::vector<double> stamps() const {
    std::vector<double> t;
    t.reserve(size());
    for (const auto& s : samples_) t.push_back(s.stamp);
    return t;
  }
  std::vector<Eigen::Vector3d> positions() const {
    std::vector<Eigen::Vector3d> p;
    p.reserve(size());
    for (const auto& s : samples_) p.push_back(s.T_world_body.translation());
    return p;
  }
  std::vector<SE3> poses() const {
    std::vector<SE3> p;
    p.reserve(size());
    for (const auto& s : samples_) p.push_back(s.T_world_body);
    return p;
  }
  /// Arc length Σ ‖p_{k+1} − p_k‖ [m].
  double path_length() const {
    double L = 0.0;
    for (std::size_t k = 1; k < size(); ++k)
      L += (samples_[k].T_world_body.translation() - samples_[k - 1].T_world_body.translation()).norm();
    return L;
  }
  /// stamp(last) − stamp(first); 0 for fewer than two samples.
  double duration() const { return size() < 2 ? 0.0 : samples_.back().stamp - samples_.front().stamp; }

  /// The samples at ids (in that order; ids may repeat but must keep stamps non-decreasing).
  Trajectory subset(const std::vector<std::size_t>& ids) const {
    Trajectory out;
    out.has_timestamps_ = has_timestamps_;
    out.metadata = metadata;
    out.samples_.reserve(ids.size());
    for (std::size_t i : ids) out.push_back(samples_.at(i));
    return out;
  }

  /// Free-form key/value metadata (e.g. "source", "estimator"), written by the slamkit format.
  std::map<std::string, std::string> metadata;

 private:
  template <class Pred>
  bool all_of(Pred pred) const {
    if (samples_.empty()) return false;
    for (const auto& s : samples_)
      if (!pred(s)) return false;
    return true;
  }

  std::vector<TrajectorySample> samples_;
  bool has_timestamps_ = true;
};

}  // namespace slamkit
