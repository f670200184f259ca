// Health of information matrices (inverse covariances) and their repair.
//
// An information matrix Ω must be symmetric and positive definite for eᵀΩe to be a
// (scaled) negative log-likelihood. Classification uses the eigenvalues λ of Ω with a
// relative tolerance τ·λmax: PD if λmin > τ·λmax, PSD-singular if |λmin| ≤ τ·λmax,
// indefinite if λmin < −τ·λmax.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

enum class InformationStatus { kPositiveDefinite, kSingular, kIndefinite, kNotSymmetric, kNotFinite };
const char* to_string(InformationStatus s);

struct InformationCheck {
  InformationStatus status = InformationStatus::kPositiveDefinite;
  double min_eigenvalue = 0.0;
  double max_eigenvalue = 0.0;
};

/// Relative tolerance τ of the classification above.
constexpr double kInformationTolerance = 1e-12;

InformationCheck check_information(const Eigen::MatrixXd& omega);

/// Nearest symmetric matrix with eigenvalues ≥ floor·λmax (the PSD cone, kept a hair inside
/// so that Ω stays invertible; floor = 1e-9 as in the derived cubicle_psd.g2o).
Eigen::MatrixXd project_to_psd(const Eigen::MatrixXd& omega, double relative_floor = 1e-9);

struct InformationHealth {
  std::size_t positive_definite = 0, singular = 0, indefinite = 0, not_symmetric = 0, not_finite = 0;
  int first_bad_line = 0;  ///< line of the first edge that is not positive definite (0: none)
  std::size_t bad() const { return singular + indefinite + not_symmetric + not_finite; }
};

InformationHealth check_information(const PoseGraph& g);

/// Projects every information matrix that is not positive definite to the PSD cone.
/// Returns how many were changed. Non-finite matrices are left alone (they are errors).
std::size_t repair_information(PoseGraph& g, double relative_floor = 1e-9);

}  // namespace slamkit
