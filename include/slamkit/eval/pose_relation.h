// Which part of an error pose E a metric measures (evo's PoseRelation, option -r):
//   trans_part      ‖t(E)‖ [m]
//   angle_deg/rad   |angle(R(E))| = ‖Log R(E)‖ [deg or rad]
//   rot_part        ‖R(E) − I‖_F (dimensionless)
//   full            ‖E − I₄‖_F (dimensionless)
//   point_distance  ATE: ‖p_est − p_ref‖; RPE: | ‖Δp_ref‖ − ‖Δp_est‖ | [m]
#pragma once

#include <string>
#include <string_view>

#include "slamkit/geometry/se3.h"

namespace slamkit {

enum class PoseRelation { kTranslation, kAngleDeg, kAngleRad, kRotationPart, kFull, kPointDistance };

/// "trans_part", "angle_deg", "angle_rad", "rot_part", "full", "point_distance".
const char* to_string(PoseRelation relation);
/// Inverse of to_string (also "trans", "rot"); throws InputError (field "pose-relation").
PoseRelation parse_pose_relation(std::string_view name);
/// "m", "deg", "rad" or "" (dimensionless).
const char* unit_of(PoseRelation relation);
/// e.g. "translation part", "rotation angle", as in evo's titles.
std::string describe(PoseRelation relation);

/// Rotation angle ‖Log R‖ in degrees.
double rotation_angle_deg(const SO3& R);

}  // namespace slamkit
