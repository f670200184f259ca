#include "slamkit/factors/between_factor.h"

#include "slamkit/core/pose_graph_error.h"

namespace slamkit {

BetweenFactorSE2::Residual BetweenFactorSE2::error(const SE2& Xi, const SE2& Xj, Jacobian<SE2>* J_i,
                                                   Jacobian<SE2>* J_j) const {
  return pose2_edge_error(measured_, measured_rotation_t_, Xi, Xj, J_i, J_j);
}

BetweenFactorSE3::Residual BetweenFactorSE3::error(const SE3& Xi, const SE3& Xj, Jacobian<SE3>* J_i,
                                                   Jacobian<SE3>* J_j) const {
  if (form_ == Se3ErrorForm::kQuaternion) return pose3_edge_error(measured_, Xi, Xj, J_i, J_j);
  // E = Z⁻¹ A, A = Xi⁻¹ Xj; Xj ⊞ δ ⇒ E Exp(δ); Xi ⊞ δ ⇒ E Exp(−Ad(A⁻¹) δ).
  const SE3 A = Xi.between(Xj);
  SE3::Jacobian J_e_E;
  const SE3::Tangent e = measured_.between(A).log(J_i || J_j ? &J_e_E : nullptr);
  if (J_j) *J_j = J_e_E;
  if (J_i) *J_i = -J_e_E * A.inverse().adjoint();
  return e;
}

}  // namespace slamkit
