// EKF-SLAM: joint Gaussian N(μ, P) over y = (x, y, θ, m_1, …, m_n).
//   predict: μ_x ← f(μ_x, u); P_xx ← F P_xx Fᵀ + Q̃; P_xm ← F P_xm (O(n)).
//   update (batch: all associated observations of one scan stacked and linearized at the
//   predicted mean): S = H P Hᵀ + R, K = P Hᵀ S⁻¹, μ ← μ + K ν (bearing of ν wrapped),
//   Joseph form P ← (I − K H) P (I − K H)ᵀ + K R Kᵀ, computed with the sparsity of H in
//   O(n² k) for k observations.
//   new landmarks (after the update, at the updated pose): m = g(x, z),
//   P_mm = G_x P_xx G_xᵀ + G_z R G_zᵀ, P_m· = G_x P_x· (full cross-covariance).
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "slamkit/filters/landmark_filter.h"

namespace slamkit {

class EkfSlam final : public LandmarkFilter {
 public:
  explicit EkfSlam(LandmarkFilterOptions options);
  std::string name() const override { return "ekf"; }
  void predict(const Control& u) override;
  void update(const std::vector<RangeBearing>& observations) override;
  Eigen::Vector3d pose() const override;
  Eigen::Matrix3d pose_covariance() const override { return P_buf_.topLeftCorner<3, 3>(); }
  std::vector<LandmarkEstimate> landmarks() const override;
  Eigen::MatrixXd joint_covariance(const std::vector<int>& landmark_ids) const override;
  const UpdateStatistics& last_update() const override { return stats_; }

  const Eigen::VectorXd& mean() const { return mu_; }
  /// P (state dimension square): a view into the preallocated storage.
  Eigen::Block<const Eigen::MatrixXd> covariance() const { return P_buf_.topLeftCorner(dim(), dim()); }

 private:
  int slot(int id) const;  // index of landmark id in μ, or −1
  Eigen::Index dim() const { return mu_.size(); }
  Eigen::Block<Eigen::MatrixXd> P() { return P_buf_.topLeftCorner(dim(), dim()); }
  void reserve_state(Eigen::Index dim);  // capacity ≥ dim, keeps P
  void add_landmark(int id, const RangeBearing& z);

  LandmarkFilterOptions o_;
  Eigen::VectorXd mu_;
  Eigen::MatrixXd P_buf_;  // capacity × capacity; P is its top-left dim() × dim() block
  std::vector<int> ids_;
  std::unordered_map<int, int> index_;  // id → k (state rows 3 + 2k)
  int next_id_ = 0;                      // ids of landmarks started under unknown association
  UpdateStatistics stats_;
};

}  // namespace slamkit
