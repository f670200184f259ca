// Edge errors of pose graphs, exactly as g2o defines them, with analytic Jacobians under
// right perturbation (X ⊞ δ = X · Exp(δ), tangent order [ρ; φ]).
//
//   pose–pose   e = t2v(Z⁻¹ · Xi⁻¹ · Xj): SE(2) → [t; θ],  SE(3) → [t; q.vec] with q.w ≥ 0
//   pose–point  e = (X · O)⁻¹ p − z      (O: optional sensor offset, identity in 2D)
// chi2 of an edge = eᵀ Ω e. With E = Z⁻¹ Xi⁻¹ Xj and J_E = ∂e(E ⊞ δ)/∂δ:
//   J_j = J_E, J_i = −J_E · Ad(Xj⁻¹ Xi).
#pragma once

#include <Eigen/Core>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Eigen::Vector3d pose2_edge_error(const SE2& Z, const SE2& Xi, const SE2& Xj,
                                 Eigen::Matrix3d* J_e_Xi = nullptr, Eigen::Matrix3d* J_e_Xj = nullptr);
/// The same with R_zᵀ = Z.rotation().matrix()ᵀ precomputed (a factor's measurement is fixed).
Eigen::Vector3d pose2_edge_error(const SE2& Z, const Eigen::Matrix2d& Rzt, const SE2& Xi, const SE2& Xj,
                                 Eigen::Matrix3d* J_e_Xi, Eigen::Matrix3d* J_e_Xj);
Vector6d pose3_edge_error(const SE3& Z, const SE3& Xi, const SE3& Xj, Matrix6d* J_e_Xi = nullptr,
                          Matrix6d* J_e_Xj = nullptr);
Eigen::Vector2d pose2_point_error(const Eigen::Vector2d& z, const SE2& X, const Eigen::Vector2d& p,
                                  Eigen::Matrix<double, 2, 3>* J_e_X = nullptr,
                                  Eigen::Matrix2d* J_e_p = nullptr);
Eigen::Vector3d pose3_point_error(const Eigen::Vector3d& z, const SE3& X, const SE3& offset,
                                  const Eigen::Vector3d& p, Eigen::Matrix<double, 3, 6>* J_e_X = nullptr,
                                  Eigen::Matrix3d* J_e_p = nullptr);

/// The error of edge e at the graph's current estimates.
Eigen::VectorXd edge_error(const PoseGraph& g, const GraphEdge& e);
/// eᵀ Ω e of edge e.
double edge_chi2(const PoseGraph& g, const GraphEdge& e);
/// Σ eᵀ Ω e over all edges (g2o's chi2).
double total_chi2(const PoseGraph& g);

}  // namespace slamkit
