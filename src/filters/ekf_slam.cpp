#include "slamkit/filters/ekf_slam.h"

#include <Eigen/Cholesky>
#include <algorithm>

#include "filter_common.h"

namespace slamkit {

using filters_detail::linearize_motion;

EkfSlam::EkfSlam(LandmarkFilterOptions options) : o_(std::move(options)) {
  filters_detail::check_filter_options(o_, "ekf");
  mu_ = o_.initial_pose;
  P_buf_.setZero(3 + 2 * Eigen::Index(o_.expected_landmarks), 3 + 2 * Eigen::Index(o_.expected_landmarks));
  P_buf_.topLeftCorner<3, 3>() = o_.initial_sigma.cwiseAbs2().asDiagonal();
}

void EkfSlam::reserve_state(Eigen::Index n) {
  if (n <= P_buf_.rows()) return;
  // Geometric growth: a map filled one landmark at a time copies P O(log n) times, not n times.
  const Eigen::Index capacity = std::max(n, P_buf_.rows() * 3 / 2);
  Eigen::MatrixXd grown(capacity, capacity);
  grown.topLeftCorner(dim(), dim()) = P();
  P_buf_.swap(grown);
}

int EkfSlam::slot(int id) const { return filters_detail::dense_slot(index_, id); }

Eigen::Vector3d EkfSlam::pose() const { return filters_detail::wrapped_pose(mu_); }

void EkfSlam::predict(const Control& u) {
  filters_detail::check_control(u, "ekf");
  const auto m = linearize_motion(o_, mu_.head<3>(), u);
  mu_.head<3>() = m.next;
  mu_(2) = wrap_angle(mu_(2));
  const Eigen::Index n = dim() - 3;
  auto P = this->P();
  P.topLeftCorner<3, 3>() = m.F * P.topLeftCorner<3, 3>() * m.F.transpose() + m.Q;
  if (n > 0) {
    P.topRightCorner(3, n) = m.F * P.topRightCorner(3, n);
    P.bottomLeftCorner(n, 3) = P.topRightCorner(3, n).transpose();
  }
}

void EkfSlam::update(const std::vector<RangeBearing>& z) {
  filters_detail::check_observations(z, "ekf");
  const std::vector<int> assoc = filters_detail::start_dense_update(
      z, pose(), ids_, [this](int id) { return slot(id); }, mu_,
      [this](const std::vector<int>& ids) { return joint_covariance(ids); }, o_, &stats_);
  if (z.empty()) return;

  // Batch update with every associated observation, linearized at the predicted mean.
  std::vector<int> rows_obs, rows_slot;
  for (std::size_t i = 0; i < z.size(); ++i)
    if (assoc[i] >= 0) rows_obs.push_back(int(i)), rows_slot.push_back(slot(assoc[i]));
  const int k = int(rows_obs.size());
  if (k > 0) {
    auto P = this->P();
    Eigen::VectorXd nu(2 * k);
    std::vector<Eigen::Matrix<double, 2, 3>> Hx(k);
    std::vector<Eigen::Matrix2d> Hm(k);
    for (int a = 0; a < k; ++a) {
      const Eigen::Vector2d lm = mu_.segment<2>(rows_slot[a]);
      o_.sensor.jacobians(mu_.head<3>(), lm, &Hx[a], &Hm[a]);
      nu.segment<2>(2 * a) = RangeBearingModel::innovation(z[rows_obs[a]], o_.sensor.predict(mu_.head<3>(), lm));
    }
    // A · Hᵀ for a dense A (rows × N), using the two non-zero column blocks of each H row pair.
    auto times_Ht = [&](const Eigen::Ref<const Eigen::MatrixXd>& A) {
      Eigen::MatrixXd out(A.rows(), 2 * k);
      for (int a = 0; a < k; ++a)
        out.middleCols<2>(2 * a) =
            A.leftCols<3>() * Hx[a].transpose() + A.middleCols<2>(rows_slot[a]) * Hm[a].transpose();
      return out;
    };
    const Eigen::MatrixXd PHt = times_Ht(P);  // N × 2k
    Eigen::MatrixXd S(2 * k, 2 * k);
    for (int a = 0; a < k; ++a)
      S.middleRows<2>(2 * a) = Hx[a] * PHt.topRows<3>() + Hm[a] * PHt.middleRows<2>(rows_slot[a]);
    for (int a = 0; a < k; ++a) S.block<2, 2>(2 * a, 2 * a) += o_.sensor.noise();
    S = 0.5 * (S + S.transpose()).eval();
    const Eigen::LDLT<Eigen::MatrixXd> S_ldlt(S);
    const Eigen::MatrixXd K = S_ldlt.solve(PHt.transpose()).transpose();  // N × 2k
    stats_.associated = k;
    stats_.nis = nu.dot(S_ldlt.solve(nu));
    stats_.nis_dof = 2 * k;
    mu_ += K * nu;
    mu_(2) = wrap_angle(mu_(2));
    // Joseph form (I − K H) P (I − K H)ᵀ + K R Kᵀ = P − K Bᵀ − B Kᵀ + K S Kᵀ with B = P Hᵀ,
    // S = H P Hᵀ + R (exact for any gain K). With M = B − ½ K S it is the symmetric rank-4k
    // update P − K Mᵀ − M Kᵀ: done in place on the lower triangle (no n × n temporary), then
    // mirrored, so P stays exactly symmetric.
    const Eigen::MatrixXd M = PHt - 0.5 * K * S;
    P.triangularView<Eigen::Lower>() -= K * M.transpose();
    P.triangularView<Eigen::Lower>() -= M * K.transpose();
    P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
  }
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (assoc[i] == kNewLandmark) {
      add_landmark(o_.association.method == AssociationMethod::kKnown ? z[i].id : next_id_++, z[i]);
      ++stats_.new_landmarks;
    } else if (assoc[i] == kRejectedObservation) {
      ++stats_.rejected;
    }
  }
}

void EkfSlam::add_landmark(int id, const RangeBearing& z) {
  Eigen::Matrix<double, 2, 3> Gx;
  Eigen::Matrix2d Gz;
  const Eigen::Vector2d m = o_.sensor.inverse(mu_.head<3>(), z, &Gx, &Gz);
  const Eigen::Index N = dim();
  reserve_state(N + 2);
  mu_.conservativeResize(N + 2);
  mu_.tail<2>() = m;
  auto P = this->P();
  const Eigen::MatrixXd cross = Gx * P.topLeftCorner(3, N);  // 2 × N
  P.bottomLeftCorner(2, N) = cross;
  P.topRightCorner(N, 2) = cross.transpose();
  P.bottomRightCorner<2, 2>() =
      Gx * P.topLeftCorner<3, 3>() * Gx.transpose() + Gz * o_.sensor.noise() * Gz.transpose();
  index_[id] = int(ids_.size());
  ids_.push_back(id);
}

std::vector<LandmarkEstimate> EkfSlam::landmarks() const {
  return filters_detail::dense_landmarks(ids_, [this](int id) { return slot(id); }, mu_, covariance());
}

Eigen::MatrixXd EkfSlam::joint_covariance(const std::vector<int>& ids) const {
  return filters_detail::dense_joint_covariance("ekf", ids, [this](int id) { return slot(id); }, covariance());
}

}  // namespace slamkit
