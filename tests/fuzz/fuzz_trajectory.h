// Shared libFuzzer harness for the trajectory readers (TUM, EuRoC/ASL, KITTI, slamkit).
//
// InputError naming the input is the expected outcome of bad input; any other exception and
// every sanitizer report is a crash. An accepted trajectory must hold only finite values and
// unit quaternions with non-decreasing stamps, and must survive write → read in its own format
// with the same values, bit for bit: stamps (and exact ns stamps where both have one), poses,
// the source rotation (KITTI), velocities, biases and metadata.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/io/trajectory_io.h"

namespace slamkit::fuzz {

[[noreturn]] inline void trajectory_violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

template <typename M>
bool same_bits(const M& a, const M& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

inline void check_sample(const TrajectorySample& s, double previous_stamp) {
  if (!std::isfinite(s.stamp) || s.stamp < previous_stamp) trajectory_violation("stamp not finite or going back");
  if (!s.T_world_body.translation().allFinite()) trajectory_violation("translation not finite");
  if (std::abs(s.T_world_body.rotation().quaternion().norm() - 1.0) > 1e-12) trajectory_violation("quaternion not unit");
  if (s.v_world && !s.v_world->allFinite()) trajectory_violation("velocity not finite");
  if (s.bias && !(s.bias->gyro.allFinite() && s.bias->accel.allFinite())) trajectory_violation("bias not finite");
}

inline void check_same(const Trajectory& a, const Trajectory& b) {
  if (a.size() != b.size()) trajectory_violation("sample counts differ");
  if (a.metadata != b.metadata) trajectory_violation("metadata differs");
  if (a.has_timestamps() != b.has_timestamps()) trajectory_violation("has_timestamps differs");
  for (std::size_t i = 0; i < a.size(); ++i) {
    const TrajectorySample& s = a[i];
    const TrajectorySample& t = b[i];
    if (std::memcmp(&s.stamp, &t.stamp, sizeof s.stamp) != 0) trajectory_violation("stamps differ");
    if (s.stamp_ns && t.stamp_ns && *s.stamp_ns != *t.stamp_ns) trajectory_violation("ns stamps differ");
    if (!same_bits(s.T_world_body.translation(), t.T_world_body.translation())) trajectory_violation("translations differ");
    if (!same_bits(s.T_world_body.rotation().quaternion().coeffs(), t.T_world_body.rotation().quaternion().coeffs()))
      trajectory_violation("rotations differ");
    if (!same_bits(s.rotation_matrix(), t.rotation_matrix())) trajectory_violation("rotation matrices differ");
    if (s.v_world.has_value() != t.v_world.has_value() || (s.v_world && !same_bits(*s.v_world, *t.v_world)))
      trajectory_violation("velocities differ");
    if (s.bias.has_value() != t.bias.has_value() ||
        (s.bias && !(same_bits(s.bias->gyro, t.bias->gyro) && same_bits(s.bias->accel, t.bias->accel))))
      trajectory_violation("biases differ");
  }
}

inline int fuzz_trajectory(const std::uint8_t* data, std::size_t size, TrajectoryFormat format, const char* name) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Trajectory traj;
  try {
    std::istringstream in(text);
    traj = read_trajectory(in, name, format);
  } catch (const InputError& e) {
    if (e.file() != name) trajectory_violation("an InputError that does not name the input");
    return 0;
  }
  double previous = -INFINITY;
  for (const TrajectorySample& s : traj) check_sample(s, previous), previous = s.stamp;

  std::ostringstream out;
  try {
    write_trajectory(out, traj, format);
  } catch (const InputError& e) {
    std::fprintf(stderr, "writing what was read failed: %s\n", e.what());
    trajectory_violation("read -> write");
  }
  Trajectory again;
  try {
    std::istringstream in(out.str());
    again = read_trajectory(in, name, format);
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading the written trajectory failed: %s\n", e.what());
    trajectory_violation("write -> read");
  }
  check_same(traj, again);
  return 0;
}

}  // namespace slamkit::fuzz
