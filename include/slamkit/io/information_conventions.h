// Information-matrix conventions of the pose-graph file formats, and the exact
// first-order conversions between them and g2o's (the convention PoseGraph stores).
//
// An information matrix belongs to an error vector: chi2 = eᵀ Ω e. If another format's
// error is, to first order at zero error, e_src = T · e_g2o, then
//   eᵀ_src Ω_src e_src = eᵀ_g2o (Tᵀ Ω_src T) e_g2o,   so   Ω_g2o = Tᵀ Ω_src T.
//
// * TORO 2D (EDGE2): the translation residual is expressed in the frame of pose i, g2o's
//   in the frame of the measurement Z = (R(dθ), t): with Xi⁻¹Xj = Z·Exp(δ), e_g2o = δ and
//   e_toro = (R(dθ) δ_xy, δθ). T = diag(R(dθ), 1), hence
//     Ω_g2o,xy = R(dθ)ᵀ Ω_toro,xy R(dθ),  Ω_g2o,xyθ = R(dθ)ᵀ Ω_toro,xyθ,  Ω_g2o,θθ = Ω_toro,θθ.
//   File order: TORO "I11 I12 I22 I33 I13 I23", g2o "I11 I12 I13 I22 I23 I33".
// * GTSAM EDGE3 / TORO EDGE3: [t; φ] with φ the rotation vector of Z⁻¹Xi⁻¹Xj; g2o uses
//   [t; q.vec] and q.vec = sin(|φ|/2) φ/|φ| ≈ φ/2, so T = diag(I, 2I):
//     Ω_g2o,tt = Ω_tt,  Ω_g2o,tq = 2 Ω_tφ,  Ω_g2o,qq = 4 Ω_φφ   (exact in floating point).
// Pure functions; thread-safe.
#pragma once

#include <Eigen/Core>
#include <string>

namespace slamkit {

/// Symmetric n×n matrix from its upper triangle listed row by row (n(n+1)/2 values).
Eigen::MatrixXd symmetric_from_upper_triangle(const double* values, int n);

/// Ω_g2o from a TORO EDGE2 information matrix (already unpacked to (x, y, θ) order).
Eigen::Matrix3d toro2d_to_g2o_information(const Eigen::Matrix3d& omega_toro, double dtheta);
/// Inverse of toro2d_to_g2o_information.
Eigen::Matrix3d g2o_to_toro2d_information(const Eigen::Matrix3d& omega_g2o, double dtheta);

/// Ω_g2o from a 6×6 information on [t; rotation vector] (GTSAM EDGE3, TORO EDGE3).
Eigen::MatrixXd rotation_vector_to_g2o_information(const Eigen::MatrixXd& omega);
/// Inverse of rotation_vector_to_g2o_information.
Eigen::MatrixXd g2o_to_rotation_vector_information(const Eigen::MatrixXd& omega_g2o);

}  // namespace slamkit
