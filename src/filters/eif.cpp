#include "slamkit/filters/eif.h"

#include <Eigen/Cholesky>

#include "filter_common.h"

namespace slamkit {

using namespace filters_detail;

Eif::Eif(LandmarkFilterOptions options) : o_(std::move(options)) {
  check_filter_options(o_, "eif");
  mu_ = o_.initial_pose;
  Omega_ = o_.initial_sigma.cwiseAbs2().cwiseInverse().asDiagonal();
  xi_ = Omega_ * mu_;
}

int Eif::slot(int id) const { return filters_detail::dense_slot(index_, id); }

Eigen::Vector3d Eif::pose() const { return filters_detail::wrapped_pose(mu_); }

const Eigen::MatrixXd& Eif::covariance() const {
  if (!sigma_valid_) {
    const Eigen::LLT<Eigen::MatrixXd> llt(Omega_);
    if (llt.info() != Eigen::Success) throw NumericalError("eif: information matrix is not positive definite");
    Sigma_ = llt.solve(Eigen::MatrixXd::Identity(Omega_.rows(), Omega_.cols()));
    Sigma_ = 0.5 * (Sigma_ + Sigma_.transpose()).eval();
    sigma_valid_ = true;
  }
  return Sigma_;
}

void Eif::recover_mean() {
  const Eigen::LLT<Eigen::MatrixXd> llt(Omega_);
  if (llt.info() != Eigen::Success) throw NumericalError("eif: information matrix is not positive definite");
  mu_ = llt.solve(xi_);
}

void Eif::predict(const Control& u) {
  check_control(u, "eif");
  const auto m = linearize_motion(o_, mu_.head<3>(), u);
  information_motion_update(m, mu_.head<3>(), &Omega_, &xi_);
  mu_.head<3>() = m.next;  // the exact mean of the linearized joint: landmarks' means unchanged
  sigma_valid_ = false;
}

void Eif::update(const std::vector<RangeBearing>& z) {
  check_observations(z, "eif");
  const std::vector<int> assoc = filters_detail::start_dense_update(
      z, pose(), ids_, [this](int id) { return slot(id); }, mu_,
      [this](const std::vector<int>& ids) { return joint_covariance(ids); }, o_, &stats_);
  if (z.empty()) return;
  std::vector<InformationFactor> factors;
  std::vector<int> slots;
  std::vector<Eigen::Vector2d> nus;
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (assoc[i] < 0) continue;
    const int s = slot(assoc[i]);
    Eigen::Vector2d nu;
    factors.push_back(measurement_factor(o_.sensor, mu_.head<3>(), mu_.segment<2>(s), z[i], &nu));
    slots.push_back(s);
    nus.push_back(nu);
  }
  const int k = int(factors.size());
  if (k > 0) {
    // NIS from the predicted covariance: S = H Σ Hᵀ + R over the stacked observations.
    const Eigen::MatrixXd& P = covariance();
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * k, mu_.size());
    Eigen::VectorXd nu(2 * k);
    for (int a = 0; a < k; ++a) {
      H.block<2, 3>(2 * a, 0) = factors[a].A_x;
      H.block<2, 2>(2 * a, slots[a]) = factors[a].A_m;
      nu.segment<2>(2 * a) = nus[a];
    }
    Eigen::MatrixXd S = H * P * H.transpose();
    for (int a = 0; a < k; ++a) S.block<2, 2>(2 * a, 2 * a) += o_.sensor.noise();
    stats_.associated = k;
    stats_.nis = nu.dot(S.ldlt().solve(nu));
    stats_.nis_dof = 2 * k;
    for (int a = 0; a < k; ++a) {
      const InformationFactor& f = factors[a];
      const int s = slots[a];
      Omega_.topLeftCorner<3, 3>() += f.A_x.transpose() * f.V * f.A_x;
      Omega_.block<3, 2>(0, s) += f.A_x.transpose() * f.V * f.A_m;
      Omega_.block<2, 3>(s, 0) = Omega_.block<3, 2>(0, s).transpose();
      Omega_.block<2, 2>(s, s) += f.A_m.transpose() * f.V * f.A_m;
      xi_.head<3>() += f.A_x.transpose() * f.V * f.y;
      xi_.segment<2>(s) += f.A_m.transpose() * f.V * f.y;
    }
    recover_mean();
    sigma_valid_ = false;
  }
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (assoc[i] == kRejectedObservation) {
      ++stats_.rejected;
      continue;
    }
    if (assoc[i] != kNewLandmark) continue;
    Eigen::Vector2d m0;
    const InformationFactor f = new_landmark_factor(o_.sensor, mu_.head<3>(), z[i], &m0);
    const Eigen::Index s = mu_.size();
    Omega_.conservativeResize(s + 2, s + 2);
    Omega_.bottomRows<2>().setZero();
    Omega_.rightCols<2>().setZero();
    xi_.conservativeResize(s + 2);
    mu_.conservativeResize(s + 2);
    Omega_.topLeftCorner<3, 3>() += f.A_x.transpose() * f.V * f.A_x;
    Omega_.block<3, 2>(0, s) = f.A_x.transpose() * f.V;
    Omega_.block<2, 3>(s, 0) = Omega_.block<3, 2>(0, s).transpose();
    Omega_.block<2, 2>(s, s) = f.V;
    xi_.head<3>() += f.A_x.transpose() * f.V * f.y;
    xi_.segment<2>(s) = f.V * f.y;
    mu_.segment<2>(s) = m0;  // = Ω⁻¹ ξ exactly: the factor is satisfied at (μ_x, m0)
    const int id = o_.association.method == AssociationMethod::kKnown ? z[i].id : next_id_++;
    index_[id] = int(ids_.size());
    ids_.push_back(id);
    ++stats_.new_landmarks;
    sigma_valid_ = false;
  }
}

std::vector<LandmarkEstimate> Eif::landmarks() const {
  return filters_detail::dense_landmarks(ids_, [this](int id) { return slot(id); }, mu_, covariance());
}

Eigen::MatrixXd Eif::joint_covariance(const std::vector<int>& ids) const {
  return filters_detail::dense_joint_covariance("eif", ids, [this](int id) { return slot(id); }, covariance());
}

}  // namespace slamkit
