#include "slamkit/core/pose_graph_error.h"

#include <cmath>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_calibration.h"

namespace slamkit {

namespace {
// R(θ) of an edge's residual angle, which is small near the optimum: below 0.1 rad from the
// Taylor series of cos and sin through θ⁸ / θ⁹ (the first omitted terms, θ¹⁰/10! and θ¹¹/11!,
// are below 3e-17 and 3e-19 relative there: the libm values to the last bit or next to it),
// else from libm. Saves one sin/cos per edge and linearization.
Eigen::Matrix2d small_angle_rotation(double t) {
  if (!(std::abs(t) < 0.1)) return SO2(t).matrix();
  const double t2 = t * t;
  const double c = 1.0 + t2 * (-1.0 / 2 + t2 * (1.0 / 24 + t2 * (-1.0 / 720 + t2 * (1.0 / 40320))));
  const double s = t * (1.0 + t2 * (-1.0 / 6 + t2 * (1.0 / 120 + t2 * (-1.0 / 5040 + t2 * (1.0 / 362880)))));
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}
}  // namespace

Eigen::Vector3d pose2_edge_error(const SE2& Z, const SE2& Xi, const SE2& Xj, Eigen::Matrix3d* J_e_Xi,
                                 Eigen::Matrix3d* J_e_Xj) {
  return pose2_edge_error(Z, Z.rotation().matrix().transpose(), Xi, Xj, J_e_Xi, J_e_Xj);
}

Eigen::Vector3d pose2_edge_error(const SE2& Z, const Eigen::Matrix2d& Rzt, const SE2& Xi, const SE2& Xj,
                                 Eigen::Matrix3d* J_e_Xi, Eigen::Matrix3d* J_e_Xj) {
  // A = Xi⁻¹ Xj = (R_iᵀ (t_j − t_i), θ_j − θ_i), E = Z⁻¹ A = (R_zᵀ (t_A − t_z), θ_A − θ_z).
  const Eigen::Matrix2d Rit = Xi.rotation().matrix().transpose();
  const Eigen::Vector2d ta = Rit * (Xj.translation() - Xi.translation());
  const double theta = wrap_angle(Xj.theta() - Xi.theta() - Z.theta());
  const Eigen::Vector2d te = Rzt * (ta - Z.translation());
  if (J_e_Xj) {  // J_E = diag(R_E, 1)
    *J_e_Xj = Eigen::Matrix3d::Identity();
    J_e_Xj->topLeftCorner<2, 2>() = small_angle_rotation(theta);
  }
  if (J_e_Xi) {  // −J_E Ad(A⁻¹) = [[−R_zᵀ, R_zᵀ (t_A,y, −t_A,x)ᵀ], [0, −1]]   (R_E R_Aᵀ = R_zᵀ)
    *J_e_Xi = Eigen::Matrix3d::Zero();
    J_e_Xi->topLeftCorner<2, 2>() = -Rzt;
    J_e_Xi->topRightCorner<2, 1>() = Rzt * Eigen::Vector2d(ta.y(), -ta.x());
    (*J_e_Xi)(2, 2) = -1.0;
  }
  return Eigen::Vector3d(te.x(), te.y(), theta);
}

Vector6d pose3_edge_error(const SE3& Z, const SE3& Xi, const SE3& Xj, Matrix6d* J_e_Xi, Matrix6d* J_e_Xj) {
  // A = Xi⁻¹ Xj, E = Z⁻¹ A, all with quaternions; matrices only where the Jacobians need them.
  const Eigen::Quaterniond& qi = Xi.rotation().quaternion();
  const Eigen::Quaterniond qz_inv = Z.rotation().quaternion().conjugate();
  const Eigen::Quaterniond qa = qi.conjugate() * Xj.rotation().quaternion();
  const Eigen::Vector3d ta = qi.conjugate() * (Xj.translation() - Xi.translation());
  const Eigen::Quaterniond q = qz_inv * qa;
  const double s = q.w() < 0.0 ? -1.0 : 1.0;  // g2o normalizes to w ≥ 0
  Vector6d e;
  e << qz_inv * (ta - Z.translation()), s * q.vec();
  if (J_e_Xi || J_e_Xj) {
    // J_E = diag(R_E, Q) with Q = ∂ vec(q ⊗ (1, φ/2)) / ∂φ = ½ (w I + [v]×). Then
    //   J_j = J_E,   J_i = −J_E Ad(A⁻¹) = [[−R_zᵀ, R_zᵀ [t_A]×], [0, −Q R_Aᵀ]]   (R_E R_Aᵀ = R_zᵀ).
    const Eigen::Matrix3d Rzt = qz_inv.toRotationMatrix();
    const Eigen::Matrix3d Q = 0.5 * s * (q.w() * Eigen::Matrix3d::Identity() + skew(q.vec()));
    if (J_e_Xj) {
      J_e_Xj->setZero();
      J_e_Xj->topLeftCorner<3, 3>() = q.toRotationMatrix();
      J_e_Xj->bottomRightCorner<3, 3>() = Q;
    }
    if (J_e_Xi) {
      J_e_Xi->topLeftCorner<3, 3>() = -Rzt;
      J_e_Xi->topRightCorner<3, 3>() = Rzt * skew(ta);
      J_e_Xi->bottomLeftCorner<3, 3>().setZero();
      J_e_Xi->bottomRightCorner<3, 3>() = -Q * qa.toRotationMatrix().transpose();
    }
  }
  return e;
}

Eigen::Vector2d pose2_point_error(const Eigen::Vector2d& z, const SE2& X, const Eigen::Vector2d& p,
                                  Eigen::Matrix<double, 2, 3>* J_e_X, Eigen::Matrix2d* J_e_p) {
  const Eigen::Matrix2d Rt = X.rotation().matrix().transpose();
  const Eigen::Vector2d local = Rt * (p - X.translation());
  // (X Exp δ)⁻¹ p ≈ local − ρ − δθ [1]× local
  if (J_e_X) *J_e_X << -1.0, 0.0, local.y(), 0.0, -1.0, -local.x();
  if (J_e_p) *J_e_p = Rt;
  return local - z;
}

Eigen::Vector3d pose3_point_error(const Eigen::Vector3d& z, const SE3& X, const SE3& offset,
                                  const Eigen::Vector3d& p, Eigen::Matrix<double, 3, 6>* J_e_X,
                                  Eigen::Matrix3d* J_e_p) {
  const Eigen::Matrix3d Rxt = X.rotation().matrix().transpose();
  const Eigen::Matrix3d Rot = offset.rotation().matrix().transpose();
  const Eigen::Vector3d q = Rxt * (p - X.translation());  // X⁻¹ p
  // (X Exp δ O)⁻¹ p = O⁻¹ Exp(−δ) q ≈ O⁻¹ (q − ρ + [q]× φ)
  if (J_e_X) {
    J_e_X->leftCols<3>() = -Rot;
    J_e_X->rightCols<3>() = Rot * skew(q);
  }
  if (J_e_p) *J_e_p = Rot * Rxt;
  return Rot * (q - offset.translation()) - z;
}

Eigen::VectorXd edge_error(const PoseGraph& g, const GraphEdge& e) {
  if (e.calibrated) return calibrated_edge_error(g, e);
  const GraphVertex& a = g.vertex(e.from);
  const GraphVertex& b = g.vertex(e.to);
  switch (e.kind) {
    case EdgeKind::kPose2Pose2: return pose2_edge_error(e.pose2, a.pose2, b.pose2);
    case EdgeKind::kPose3Pose3: return pose3_edge_error(e.pose3, a.pose3, b.pose3);
    case EdgeKind::kPose2Point2: return pose2_point_error(e.point.head<2>(), a.pose2, b.point.head<2>());
    case EdgeKind::kPose3Point3: {
      const auto it = g.sensor_offsets.find(e.sensor_offset_id);
      const SE3 offset = it == g.sensor_offsets.end() ? SE3() : it->second;
      return pose3_point_error(e.point, a.pose3, offset, b.point);
    }
  }
  throw InputError(g.source, e.line, "", "unknown edge kind");
}

namespace {
// eᵀ Ω e with a fixed-size error (no heap allocation on the hot path).
template <int N>
double quadratic_form(const Eigen::Matrix<double, N, 1>& e, const Eigen::MatrixXd& omega) {
  return e.dot(omega.topLeftCorner<N, N>() * e);
}
}  // namespace

double edge_chi2(const PoseGraph& g, const GraphEdge& e) {
  if (e.calibrated) {
    const Eigen::VectorXd r = calibrated_edge_error(g, e);
    return r.dot(e.information * r);
  }
  const GraphVertex& a = g.vertex(e.from);
  const GraphVertex& b = g.vertex(e.to);
  switch (e.kind) {
    case EdgeKind::kPose2Pose2: return quadratic_form<3>(pose2_edge_error(e.pose2, a.pose2, b.pose2), e.information);
    case EdgeKind::kPose3Pose3: return quadratic_form<6>(pose3_edge_error(e.pose3, a.pose3, b.pose3), e.information);
    case EdgeKind::kPose2Point2:
      return quadratic_form<2>(pose2_point_error(e.point.head<2>(), a.pose2, b.point.head<2>()), e.information);
    case EdgeKind::kPose3Point3: {
      const auto it = g.sensor_offsets.find(e.sensor_offset_id);
      const SE3 offset = it == g.sensor_offsets.end() ? SE3() : it->second;
      return quadratic_form<3>(pose3_point_error(e.point, a.pose3, offset, b.point), e.information);
    }
  }
  throw InputError(g.source, e.line, "", "unknown edge kind");
}

double total_chi2(const PoseGraph& g) {
  double chi2 = 0.0;
  for (const auto& e : g.edges) chi2 += edge_chi2(g, e);
  return chi2;
}

}  // namespace slamkit
