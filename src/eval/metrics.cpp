#include "slamkit/eval/metrics.h"

#include <cmath>

#include "slamkit/core/error.h"

namespace slamkit {

namespace {

void check_associated(const Trajectory& est, const Trajectory& ref) {
  if (est.size() != ref.size())
    throw Error("metric: trajectories are not associated (" + std::to_string(est.size()) + " vs " +
                std::to_string(ref.size()) + " poses)");
  if (est.empty()) throw Error("metric: empty trajectories");
}

// [R | t] on the rotation matrices as read (TrajectorySample::rotation_matrix()), with the
// inverse [Rᵀ | −Rᵀ t], as evo computes: for KITTI files whose matrices are not exactly
// orthonormal this reproduces evo's numbers to round-off instead of to ~1e-6.
struct Rigid {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  static Rigid of(const TrajectorySample& s) { return {s.rotation_matrix(), s.T_world_body.translation()}; }
  /// this⁻¹ · other
  Rigid between(const Rigid& o) const { return {R.transpose() * o.R, R.transpose() * (o.t - t)}; }
};

double angle_deg(const Eigen::Matrix3d& R) { return rotation_angle_deg(SO3::from_matrix(R)); }

double error_of(const Rigid& E, PoseRelation relation) {
  switch (relation) {
    case PoseRelation::kTranslation:
    case PoseRelation::kPointDistance: return E.t.norm();
    case PoseRelation::kAngleDeg: return angle_deg(E.R);
    case PoseRelation::kAngleRad: return SO3::from_matrix(E.R).log().norm();
    case PoseRelation::kRotationPart: return (E.R - Eigen::Matrix3d::Identity()).norm();
    case PoseRelation::kFull: return std::sqrt((E.R - Eigen::Matrix3d::Identity()).squaredNorm() + E.t.squaredNorm());
  }
  return 0.0;
}

}  // namespace

PoseErrors compute_ate(const Trajectory& est, const Trajectory& ref, PoseRelation relation) {
  check_associated(est, ref);
  PoseErrors out;
  const std::size_t n = est.size();
  out.errors.reserve(n);
  out.translation.reserve(n);
  out.rotation_deg.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Rigid P = Rigid::of(est[k]), Q = Rigid::of(ref[k]);
    const Rigid E = P.between(Q);  // P⁻¹ Q
    const double trans = (P.t - Q.t).norm();
    out.translation.push_back(trans);
    out.rotation_deg.push_back(angle_deg(E.R));
    const bool positional = relation == PoseRelation::kTranslation || relation == PoseRelation::kPointDistance;
    out.errors.push_back(positional ? trans : error_of(E, relation));
  }
  return out;
}

RpeErrors compute_rpe(const Trajectory& est, const Trajectory& ref, const RpeOptions& options) {
  check_associated(est, ref);
  RpeErrors out;
  out.pairs = select_pairs(options.pairs_from_reference ? ref : est, options.delta, options.delta_unit,
                           options.all_pairs, options.rel_tol);
  out.errors.reserve(out.pairs.size());
  out.translation.reserve(out.pairs.size());
  out.rotation_deg.reserve(out.pairs.size());
  for (const auto& [i, j] : out.pairs) {
    const Rigid Q_rel = Rigid::of(ref[i]).between(Rigid::of(ref[j]));
    const Rigid P_rel = Rigid::of(est[i]).between(Rigid::of(est[j]));
    const Rigid E = Q_rel.between(P_rel);  // (Q_i⁻¹ Q_j)⁻¹ (P_i⁻¹ P_j)
    out.translation.push_back(E.t.norm());
    out.rotation_deg.push_back(angle_deg(E.R));
    if (options.relation == PoseRelation::kPointDistance) {
      const double d_ref = (ref[i].T_world_body.translation() - ref[j].T_world_body.translation()).norm();
      const double d_est = (est[i].T_world_body.translation() - est[j].T_world_body.translation()).norm();
      out.errors.push_back(std::abs(d_ref - d_est));
    } else {
      out.errors.push_back(error_of(E, options.relation));
    }
  }
  return out;
}

}  // namespace slamkit
