// Alignment of an estimated trajectory to its reference before computing errors.
//
// The estimate and reference must already be associated (sample k ↔ sample k). The
// alignment S = (s, R, t) is applied from the left to every estimated pose, as evo does:
//   p' = s R p + t,   R'_world_body = R R_world_body,   v' = s R v (biases unchanged).
// Modes:
//   none    S = identity.
//   origin  S = T_ref[0] · T_est[0]⁻¹ (evo's --align_origin): the first poses coincide.
//   se3     Umeyama on positions, rigid (evo -a).
//   sim3    Umeyama on positions with scale (evo -as); for monocular estimates.
//   4dof    rotation about the reference's z axis (gravity) + translation, for visual-inertial
//           estimates whose roll and pitch are observable.
//   scale   only the Umeyama scale s (evo -s), p' = s p.
// Only the first n_first associated pairs are used to estimate S when n_first > 0.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "slamkit/core/trajectory.h"
#include "slamkit/geometry/umeyama.h"

namespace slamkit {

enum class AlignmentMode { kNone, kOrigin, kSe3, kSim3, kPosYaw, kScale };

/// "none", "origin", "se3", "sim3", "4dof", "scale".
const char* to_string(AlignmentMode mode);
/// Inverse of to_string (also "posyaw" for 4dof); throws InputError (field "align") otherwise.
AlignmentMode parse_alignment_mode(std::string_view name);
/// Human description, e.g. "SE(3) Umeyama alignment".
std::string describe(AlignmentMode mode);

/// S taking est onto ref (same length, associated). Throws slamkit::Error if the
/// configuration is degenerate (e.g. a straight-line trajectory for se3/sim3).
Similarity3 compute_alignment(const Trajectory& est, const Trajectory& ref, AlignmentMode mode,
                              std::size_t n_first = 0);

/// est with S applied to every sample (see the header comment).
Trajectory apply_alignment(const Trajectory& est, const Similarity3& S);

}  // namespace slamkit
