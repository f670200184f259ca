#include "slamkit/eval/pose_relation.h"

#include "slamkit/core/error.h"

namespace slamkit {

const char* to_string(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslation: return "trans_part";
    case PoseRelation::kAngleDeg: return "angle_deg";
    case PoseRelation::kAngleRad: return "angle_rad";
    case PoseRelation::kRotationPart: return "rot_part";
    case PoseRelation::kFull: return "full";
    case PoseRelation::kPointDistance: return "point_distance";
  }
  return "?";
}

PoseRelation parse_pose_relation(std::string_view name) {
  if (name == "trans_part" || name == "trans") return PoseRelation::kTranslation;
  if (name == "angle_deg") return PoseRelation::kAngleDeg;
  if (name == "angle_rad") return PoseRelation::kAngleRad;
  if (name == "rot_part" || name == "rot") return PoseRelation::kRotationPart;
  if (name == "full") return PoseRelation::kFull;
  if (name == "point_distance") return PoseRelation::kPointDistance;
  throw InputError("", 0, "pose-relation", "unknown pose relation '" + std::string(name) +
                                               "' (expected trans_part, angle_deg, angle_rad, rot_part, full, point_distance)");
}

const char* unit_of(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslation:
    case PoseRelation::kPointDistance: return "m";
    case PoseRelation::kAngleDeg: return "deg";
    case PoseRelation::kAngleRad: return "rad";
    default: return "";
  }
}

std::string describe(PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslation: return "translation part";
    case PoseRelation::kAngleDeg:
    case PoseRelation::kAngleRad: return "rotation angle";
    case PoseRelation::kRotationPart: return "rotation part";
    case PoseRelation::kFull: return "full transformation";
    case PoseRelation::kPointDistance: return "point distance";
  }
  return "?";
}

double rotation_angle_deg(const SO3& R) { return R.log().norm() * 180.0 / kPi; }

}  // namespace slamkit
