// Trajectory readers and writers: TUM, EuRoC/ASL CSV, KITTI and slamkit's own format.
//
//   tum      "t x y z qx qy qz qw" (seconds, quaternion w LAST), space separated, '#' comments.
//   euroc    ASL CSV "t_ns, x, y, z, qw, qx, qy, qz [, vx, vy, vz [, bgx, bgy, bgz, bax, bay, baz]]"
//            (integer ns, quaternion w FIRST; 8, 11 or 17 columns; header line '#...').
//   kitti    12 numbers per line, the first three rows of T_world_cam row-major; no time:
//            stamps are the line indices and has_timestamps() is false.
//   slamkit  TUM plus a first line "# slamkit trajectory 1", metadata lines "# meta KEY=VALUE"
//            and optional state columns: 8, 11 (+ v_world) or 17 (+ v_world, b_g, b_a) fields.
//
// Readers are strict: every malformed line throws InputError "FILE:LINE: field 'F': message"
// (wrong field count, rows with a different column layout than the first, bad number, stamps
// going back in time, quaternion or rotation far from unit/orthonormal). Quaternions within 1e-2 of unit norm are normalized; KITTI rotations
// are projected onto SO(3). Decimal TUM/slamkit stamps with at most 9 fraction digits keep
// their exact value in ns. Writers print the shortest text that reads back to the same
// double, and exact ns stamps as "s.nnnnnnnnn", so write → read round trips are lossless.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "slamkit/core/trajectory.h"

namespace slamkit {

enum class TrajectoryFormat { kTum, kEuroc, kKitti, kSlamkit };

const char* to_string(TrajectoryFormat format);
/// "tum", "euroc" (or "asl"), "kitti", "slamkit"; anything else throws InputError (field "format").
TrajectoryFormat parse_trajectory_format(std::string_view name);
/// Guesses a file's format: the slamkit header line → slamkit; a ".csv" name → euroc;
/// a first data line of 12 fields → kitti; otherwise tum. Throws InputError if unreadable.
TrajectoryFormat detect_trajectory_format(const std::string& path);

Trajectory read_tum(std::istream& in, const std::string& source);
Trajectory read_euroc(std::istream& in, const std::string& source);
Trajectory read_kitti(std::istream& in, const std::string& source);
Trajectory read_slamkit_trajectory(std::istream& in, const std::string& source);
Trajectory read_trajectory(std::istream& in, const std::string& source, TrajectoryFormat format);
/// Reads a file; an empty file (no samples) is an error.
Trajectory read_trajectory(const std::string& path, TrajectoryFormat format);
Trajectory read_trajectory(const std::string& path);  ///< format from detect_trajectory_format()

void write_tum(std::ostream& out, const Trajectory& trajectory);
/// 17 columns when every sample has velocity and biases, 11 with velocity only, else 8. Stamps
/// without ns are rounded to ns.
void write_euroc(std::ostream& out, const Trajectory& trajectory);
void write_kitti(std::ostream& out, const Trajectory& trajectory);
/// 17 columns with velocity and biases, 11 with velocity only, else 8; metadata in the header.
void write_slamkit_trajectory(std::ostream& out, const Trajectory& trajectory);
void write_trajectory(std::ostream& out, const Trajectory& trajectory, TrajectoryFormat format);
/// Writes a file; throws InputError(path, 0, ...) if it cannot.
void write_trajectory(const std::string& path, const Trajectory& trajectory, TrajectoryFormat format);

}  // namespace slamkit
