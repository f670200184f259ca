#include "slamkit/core/information.h"

#include <Eigen/Eigenvalues>

namespace slamkit {

const char* to_string(InformationStatus s) {
  switch (s) {
    case InformationStatus::kPositiveDefinite: return "positive definite";
    case InformationStatus::kSingular: return "singular (positive semidefinite)";
    case InformationStatus::kIndefinite: return "indefinite";
    case InformationStatus::kNotSymmetric: return "not symmetric";
    case InformationStatus::kNotFinite: return "not finite";
  }
  return "?";
}

InformationCheck check_information(const Eigen::MatrixXd& omega) {
  InformationCheck c;
  if (omega.size() == 0 || !omega.allFinite()) {
    c.status = InformationStatus::kNotFinite;
    return c;
  }
  const double scale = omega.cwiseAbs().maxCoeff();
  if ((omega - omega.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    c.status = InformationStatus::kNotSymmetric;
    return c;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(omega, Eigen::EigenvaluesOnly);
  c.min_eigenvalue = eig.eigenvalues().minCoeff();
  c.max_eigenvalue = eig.eigenvalues().maxCoeff();
  const double tol = kInformationTolerance * std::max(std::abs(c.max_eigenvalue), std::abs(c.min_eigenvalue));
  if (c.min_eigenvalue > tol) {
    c.status = InformationStatus::kPositiveDefinite;
  } else if (c.min_eigenvalue >= -tol) {
    c.status = InformationStatus::kSingular;
  } else {
    c.status = InformationStatus::kIndefinite;
  }
  return c;
}

Eigen::MatrixXd project_to_psd(const Eigen::MatrixXd& omega, double relative_floor) {
  const Eigen::MatrixXd sym = 0.5 * (omega + omega.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(sym);
  Eigen::VectorXd lambda = eig.eigenvalues();
  const double floor = relative_floor * std::max(lambda.maxCoeff(), 0.0);
  lambda = lambda.cwiseMax(floor);
  const Eigen::MatrixXd P = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
  return 0.5 * (P + P.transpose());  // exactly symmetric, not just to rounding
}

InformationHealth check_information(const PoseGraph& g) {
  InformationHealth h;
  for (const auto& e : g.edges) {
    const InformationCheck c = check_information(e.information);
    switch (c.status) {
      case InformationStatus::kPositiveDefinite: ++h.positive_definite; continue;
      case InformationStatus::kSingular: ++h.singular; break;
      case InformationStatus::kIndefinite: ++h.indefinite; break;
      case InformationStatus::kNotSymmetric: ++h.not_symmetric; break;
      case InformationStatus::kNotFinite: ++h.not_finite; break;
    }
    if (h.first_bad_line == 0) h.first_bad_line = e.line;
  }
  return h;
}

std::size_t repair_information(PoseGraph& g, double relative_floor) {
  std::size_t changed = 0;
  for (auto& e : g.edges) {
    const InformationStatus s = check_information(e.information).status;
    if (s == InformationStatus::kPositiveDefinite || s == InformationStatus::kNotFinite) continue;
    e.information = project_to_psd(e.information, relative_floor);
    ++changed;
  }
  return changed;
}

}  // namespace slamkit
