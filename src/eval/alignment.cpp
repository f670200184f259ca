#include "slamkit/eval/alignment.h"

#include <Eigen/Geometry>
#include <stdexcept>

#include "slamkit/core/error.h"

namespace slamkit {

const char* to_string(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::kNone: return "none";
    case AlignmentMode::kOrigin: return "origin";
    case AlignmentMode::kSe3: return "se3";
    case AlignmentMode::kSim3: return "sim3";
    case AlignmentMode::kPosYaw: return "4dof";
    case AlignmentMode::kScale: return "scale";
  }
  return "?";
}

AlignmentMode parse_alignment_mode(std::string_view name) {
  if (name == "none") return AlignmentMode::kNone;
  if (name == "origin") return AlignmentMode::kOrigin;
  if (name == "se3") return AlignmentMode::kSe3;
  if (name == "sim3") return AlignmentMode::kSim3;
  if (name == "4dof" || name == "posyaw") return AlignmentMode::kPosYaw;
  if (name == "scale") return AlignmentMode::kScale;
  throw InputError("", 0, "align", "unknown alignment '" + std::string(name) +
                                       "' (expected se3, sim3, 4dof, origin, scale or none)");
}

std::string describe(AlignmentMode mode) {
  switch (mode) {
    case AlignmentMode::kNone: return "not aligned";
    case AlignmentMode::kOrigin: return "origin alignment";
    case AlignmentMode::kSe3: return "SE(3) Umeyama alignment";
    case AlignmentMode::kSim3: return "Sim(3) Umeyama alignment";
    case AlignmentMode::kPosYaw: return "position + yaw (4-DoF) alignment";
    case AlignmentMode::kScale: return "scale correction only";
  }
  return "?";
}

Similarity3 compute_alignment(const Trajectory& est, const Trajectory& ref, AlignmentMode mode,
                              std::size_t n_first) {
  if (est.size() != ref.size()) throw Error("alignment: trajectories are not associated (different lengths)");
  if (est.empty()) throw Error("alignment: empty trajectories");
  if (mode == AlignmentMode::kNone) return Similarity3{};
  if (mode == AlignmentMode::kOrigin) {
    // T_ref0 · T_est0⁻¹ on the rotation matrices as read (see TrajectorySample::source_rotation).
    Similarity3 out;
    out.R = ref[0].rotation_matrix() * est[0].rotation_matrix().transpose();
    out.t = ref[0].T_world_body.translation() - out.R * est[0].T_world_body.translation();
    return out;
  }
  const std::size_t n = n_first > 0 && n_first < est.size() ? n_first : est.size();
  Eigen::Matrix3Xd src(3, static_cast<Eigen::Index>(n)), dst(3, static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) {
    src.col(static_cast<Eigen::Index>(k)) = est[k].T_world_body.translation();
    dst.col(static_cast<Eigen::Index>(k)) = ref[k].T_world_body.translation();
  }
  try {
    switch (mode) {
      case AlignmentMode::kSe3: return umeyama(src, dst, false);
      case AlignmentMode::kSim3: return umeyama(src, dst, true);
      case AlignmentMode::kPosYaw: return umeyama_yaw(src, dst);
      case AlignmentMode::kScale: {
        Similarity3 out;
        out.scale = umeyama(src, dst, true).scale;
        return out;
      }
      default: break;
    }
  } catch (const std::invalid_argument& e) {
    throw Error(std::string("alignment (") + to_string(mode) + ") failed: " + e.what());
  }
  throw Error("alignment: unsupported mode");
}

Trajectory apply_alignment(const Trajectory& est, const Similarity3& S) {
  const Eigen::Quaterniond q_s(S.R);
  Trajectory out = est;
  for (std::size_t k = 0; k < out.size(); ++k) {
    TrajectorySample& s = out[k];
    const Eigen::Vector3d p = S.apply(s.T_world_body.translation());
    s.T_world_body = SE3(SO3(q_s * s.T_world_body.rotation().quaternion()), p);
    if (s.source_rotation) *s.source_rotation = S.R * *s.source_rotation;
    if (s.v_world) *s.v_world = S.scale * (S.R * *s.v_world);
  }
  return out;
}

}  // namespace slamkit
