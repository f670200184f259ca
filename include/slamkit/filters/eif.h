// Extended information filter SLAM (P2): the canonical form Ω = P⁻¹, ξ = Ω μ, dense.
//   predict: augment with the new pose, marginalize the old one (Schur complement), see
//            information_motion_update in src/filters/filter_common.h; μ_x ← f(μ_x).
//   update (batch, linearized at the predicted mean): Ω += Hᵀ R⁻¹ H, ξ += Hᵀ R⁻¹ (ν + H μ);
//            then μ = Ω⁻¹ ξ (Cholesky, O(n³)); new landmarks enter as the factor
//            m − G_x x = g(μ_x, z) − G_x μ_x with information (G_z R G_zᵀ)⁻¹.
// Algebraically equal to the EKF (tested to 1e-9); the reference for SEIF.
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "slamkit/filters/landmark_filter.h"

namespace slamkit {

class Eif final : public LandmarkFilter {
 public:
  explicit Eif(LandmarkFilterOptions options);
  std::string name() const override { return "eif"; }
  void predict(const Control& u) override;
  void update(const std::vector<RangeBearing>& observations) override;
  Eigen::Vector3d pose() const override;
  Eigen::Matrix3d pose_covariance() const override { return covariance().topLeftCorner<3, 3>(); }
  std::vector<LandmarkEstimate> landmarks() const override;
  Eigen::MatrixXd joint_covariance(const std::vector<int>& landmark_ids) const override;
  const UpdateStatistics& last_update() const override { return stats_; }

  const Eigen::MatrixXd& information() const { return Omega_; }
  const Eigen::VectorXd& information_vector() const { return xi_; }
  const Eigen::VectorXd& mean() const { return mu_; }
  /// Ω⁻¹ (computed on demand, cached until the next change).
  const Eigen::MatrixXd& covariance() const;

 private:
  int slot(int id) const;
  void recover_mean();

  LandmarkFilterOptions o_;
  Eigen::MatrixXd Omega_;
  Eigen::VectorXd xi_, mu_;
  mutable Eigen::MatrixXd Sigma_;
  mutable bool sigma_valid_ = false;
  std::vector<int> ids_;
  std::unordered_map<int, int> index_;
  int next_id_ = 0;
  UpdateStatistics stats_;
};

}  // namespace slamkit
