// Reading and writing BAL bundle-adjustment files (core/bal_problem.h has the camera model).
//
//   <num_cameras> <num_points> <num_observations>
//   <camera> <point> <x> <y>        num_observations records, 0-based indices
//   <9 camera parameters>           per camera: ω (3), t (3), f, k1, k2
//   <3 point coordinates>           per point
// Values are whitespace-separated tokens; line breaks and blank lines between them are
// free (the GRAIL files put one value per line, some copies several). The reader is strict:
// a count that is not a positive integer, an index out of range (an observation of a missing
// camera or point), a value that is not a finite number, a truncated file or data after the
// last point throw InputError naming the file, the line and the field
// ("problem.txt:17: field 'camera 2 f': not a number: 'x'"). Comment lines ('#') are skipped.
// The writer prints the shortest round-trip text of every double: read → write → read is
// bit-identical.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "slamkit/core/bal_problem.h"

namespace slamkit {

struct BalReadReport {
  std::vector<std::string> warnings;  ///< e.g. points seen by fewer than 2 cameras
};

BalProblem read_bal(std::istream& in, const std::string& source, BalReadReport* report = nullptr);
BalProblem read_bal(const std::string& path, BalReadReport* report = nullptr);

void write_bal(std::ostream& out, const BalProblem& p);
void write_bal(const std::string& path, const BalProblem& p);
std::string bal_to_string(const BalProblem& p);

/// True for paths that look like BAL files: *.bal, problem-*.txt, *-pre.txt.
bool looks_like_bal_path(const std::string& path);

/// Throws InputError naming the observation's line (standard one-record-per-line layout) if a
/// predicted pixel is not finite (a point on a camera's plane, overflow). Points behind every
/// camera that observes them, and observations behind their camera, are reported as warnings
/// (the real BAL files contain some; they stay finite and are optimized like the rest).
void validate_bal_geometry(const BalProblem& p, BalReadReport* report = nullptr);

/// Writes the points and camera centres as an ASCII PLY (points white, cameras green).
void write_bal_ply(const std::string& path, const BalProblem& p);

}  // namespace slamkit
