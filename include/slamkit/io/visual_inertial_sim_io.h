// The text format of a simulated visual-inertial run (docs/formats.md, "Visual-inertial
// simulation"): header records (camera, T_cam_imu, IMU noise, gravity, ...), then landmarks,
// moving groups, IMU samples each followed by its true state, and frames each followed by
// its observations. Every double is written in its shortest round-trip form, so a run reads
// back with the same values (T_cam_imu up to the 1-ulp renormalization of its quaternion)
// and replays exactly; the text of a file once read is a fixed point of read → write.
// The reader is strict: unknown or repeated records, wrong field counts, bad numbers, times
// out of order, a truth line that does not follow its IMU line, a frame at a time with no IMU
// sample, observation counts that disagree, unknown landmarks or groups, and labels that
// disagree with the landmark's group all throw InputError "FILE:LINE: field 'F': message".
#pragma once

#include <iosfwd>
#include <string>

#include "slamkit/sim/visual_inertial_sim.h"

namespace slamkit {

VisualInertialSim read_visual_inertial_sim(std::istream& in, const std::string& source);
VisualInertialSim read_visual_inertial_sim(const std::string& path);
/// Throws std::invalid_argument if the run has no camera or a non-finite number.
void write_visual_inertial_sim(std::ostream& out, const VisualInertialSim& sim);
/// Atomic write (a temporary file renamed into place); throws InputError if it cannot.
void write_visual_inertial_sim(const std::string& path, const VisualInertialSim& sim);

}  // namespace slamkit
