// Pieces the Gaussian filters (EKF, EIF, SEIF) share: the linearized motion step and the
// options check. Private to src/filters.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include "slamkit/core/error.h"
#include "slamkit/filters/data_association.h"
#include "slamkit/filters/landmark_filter.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit::filters_detail {

/// x' ≈ f(μ) + F (x − μ) + w, w ~ N(0, Q̃), Q̃ = F_u Q(u) F_uᵀ + diag(floor²).
/// `next` keeps θ continuous (θ' = θ + wrap(f_θ − θ)), for the information forms whose ξ
/// must stay equal to Ω μ.
struct LinearizedMotion {
  Eigen::Vector3d next;
  Eigen::Matrix3d F;
  Eigen::Matrix3d Q;
};

inline LinearizedMotion linearize_motion(const LandmarkFilterOptions& o, const Eigen::Vector3d& pose,
                                         const Control& u) {
  LinearizedMotion m;
  Eigen::Matrix<double, 3, 2> F_u;
  o.motion->jacobians(pose, u, &m.F, &F_u);
  m.next = o.motion->predict(pose, u);
  m.next.z() = pose.z() + wrap_angle(m.next.z() - pose.z());
  m.Q = F_u * o.motion->control_noise(u) * F_u.transpose();
  m.Q.diagonal() += o.pose_noise_floor.cwiseAbs2();
  return m;
}

/// Information-form motion update by augment-then-marginalize (P2), on a dense (Ω, ξ) whose
/// rows 0..2 are the pose and rows 3.. anything linked to it (EIF: every landmark; SEIF: the
/// active ones; nothing else changes). With W = Q̃⁻¹, c = f(μ) − F μ, S = Ω_xx + Fᵀ W F and
/// ξ̂_x = ξ_x − Fᵀ W c, the old pose x is marginalized out of the joint over (x, x', r):
///   Ω'_x'x' = W − W F S⁻¹ Fᵀ W,  Ω'_x'r = W F S⁻¹ Ω_xr,  Ω'_rr = Ω_rr − Ω_rx S⁻¹ Ω_xr,
///   ξ'_x' = W c + W F S⁻¹ ξ̂_x,   ξ'_r = ξ_r − Ω_rx S⁻¹ ξ̂_x.
inline void information_motion_update(const LinearizedMotion& m, const Eigen::Vector3d& mu_x,
                                      Eigen::MatrixXd* Omega, Eigen::VectorXd* xi) {
  const Eigen::Index n = Omega->rows() - 3;
  const Eigen::Matrix3d W = m.Q.inverse();
  const Eigen::Vector3d c = m.next - m.F * mu_x;
  const Eigen::Matrix3d WF = W * m.F;
  const Eigen::Matrix3d S = Omega->topLeftCorner<3, 3>() + m.F.transpose() * WF;
  const Eigen::Matrix3d S_inv = S.inverse();
  const Eigen::Vector3d xi_hat = xi->head<3>() - WF.transpose() * c;
  const Eigen::Matrix3d WF_Sinv = WF * S_inv;
  if (n > 0) {
    const Eigen::MatrixXd Orx = Omega->bottomLeftCorner(n, 3);
    const Eigen::MatrixXd Orx_Sinv = Orx * S_inv;
    Omega->bottomRightCorner(n, n).noalias() -= Orx_Sinv * Orx.transpose();
    xi->tail(n).noalias() -= Orx_Sinv * xi_hat;
    Omega->bottomLeftCorner(n, 3) = Orx_Sinv * WF.transpose();  // (W F S⁻¹ Ω_xr)ᵀ
    Omega->topRightCorner(3, n) = Omega->bottomLeftCorner(n, 3).transpose();
  }
  Eigen::Matrix3d Oxx = W - WF_Sinv * WF.transpose();
  Omega->topLeftCorner<3, 3>() = 0.5 * (Oxx + Oxx.transpose());
  xi->head<3>() = W * c + WF_Sinv * xi_hat;
}

/// A linearized 2-D factor between the pose and one landmark, r = y − A_x x − A_m m with
/// information V: adding it is Ω += Aᵀ V A, ξ += Aᵀ V y.
struct InformationFactor {
  Eigen::Matrix<double, 2, 3> A_x;
  Eigen::Matrix2d A_m;
  Eigen::Matrix2d V;
  Eigen::Vector2d y;
};

/// Observation z of a mapped landmark: A = H at (μ_x, μ_m), y = ν + H μ (ν bearing-wrapped).
inline InformationFactor measurement_factor(const RangeBearingModel& sensor, const Eigen::Vector3d& mu_x,
                                            const Eigen::Vector2d& mu_m, const RangeBearing& z,
                                            Eigen::Vector2d* innovation = nullptr) {
  InformationFactor f;
  sensor.jacobians(mu_x, mu_m, &f.A_x, &f.A_m);
  f.V = sensor.noise().inverse();
  const Eigen::Vector2d nu = RangeBearingModel::innovation(z, sensor.predict(mu_x, mu_m));
  if (innovation) *innovation = nu;
  f.y = nu + f.A_x * mu_x + f.A_m * mu_m;
  return f;
}

/// A new landmark m = g(μ_x, z) + G_x (x − μ_x) + G_z v: the factor m − G_x x = m0 − G_x μ_x
/// with V = (G_z R G_zᵀ)⁻¹, the information form of the EKF's initialization with full
/// cross-covariance. Returns the factor; *m0 = g(μ_x, z).
inline InformationFactor new_landmark_factor(const RangeBearingModel& sensor, const Eigen::Vector3d& mu_x,
                                             const RangeBearing& z, Eigen::Vector2d* m0) {
  InformationFactor f;
  Eigen::Matrix<double, 2, 3> Gx;
  Eigen::Matrix2d Gz;
  *m0 = sensor.inverse(mu_x, z, &Gx, &Gz);
  f.A_x = -Gx;
  f.A_m = Eigen::Matrix2d::Identity();
  f.V = (Gz * sensor.noise() * Gz.transpose()).inverse();
  f.y = *m0 - Gx * mu_x;
  return f;
}

/// Row of landmark `id` in a dense state [pose; landmark 0; landmark 1; ...] (3 + 2k), or −1.
inline int dense_slot(const std::unordered_map<int, int>& index, int id) {
  const auto it = index.find(id);
  return it == index.end() ? -1 : 3 + 2 * it->second;
}

/// The pose part of a dense mean with its heading wrapped.
inline Eigen::Vector3d wrapped_pose(const Eigen::VectorXd& mu) {
  Eigen::Vector3d p = mu.head<3>();
  p.z() = wrap_angle(p.z());
  return p;
}

inline void check_filter_options(const LandmarkFilterOptions& o, const char* filter) {
  if (!o.motion) throw InputError(filter, 0, "motion", "no motion model");
  if (!(o.initial_sigma.array() > 0).all() || !o.initial_sigma.allFinite())
    throw InputError(filter, 0, "initial_sigma", "must be positive and finite");
  if (!o.initial_pose.allFinite()) throw InputError(filter, 0, "initial_pose", "not finite");
  if (!(o.pose_noise_floor.array() >= 0).all()) throw InputError(filter, 0, "pose_noise_floor", "negative");
  if (o.expected_landmarks < 0) throw InputError(filter, 0, "expected_landmarks", "negative");
}

inline void check_control(const Control& u, const char* filter) {
  if (!std::isfinite(u.v) || !std::isfinite(u.turn) || !(u.dt >= 0) || !std::isfinite(u.dt))
    throw InputError(filter, 0, "control", "not finite (v, turn, dt) or negative dt");
}

inline void check_observations(const std::vector<RangeBearing>& z, const char* filter) {
  for (const auto& o : z)
    if (!(o.range > 0) || !std::isfinite(o.range) || !std::isfinite(o.bearing))
      throw InputError(filter, 0, "observation", "range must be positive and finite, bearing finite");
}

/// The shared start of a dense filter's update (EKF, EIF): reset the statistics, then associate
/// the scan with the mapped landmarks, whose means sit in μ at slot(id). Returns one entry per
/// observation (landmark id, kNewLandmark or kRejectedObservation); empty for an empty scan.
template <class Slot, class JointCovariance>
std::vector<int> start_dense_update(const std::vector<RangeBearing>& z, const Eigen::Vector3d& pose,
                                    const std::vector<int>& ids, const Slot& slot, const Eigen::VectorXd& mu,
                                    const JointCovariance& joint_covariance, const LandmarkFilterOptions& o,
                                    UpdateStatistics* stats) {
  *stats = UpdateStatistics{};
  stats->observations = int(z.size());
  if (z.empty()) return {};
  std::vector<Eigen::Vector2d> means;
  means.reserve(ids.size());
  for (int id : ids) means.push_back(mu.segment<2>(slot(id)));
  return associate_landmarks(z, pose, ids, means, joint_covariance, o.sensor, o.association);
}

/// landmarks() and joint_covariance() of a filter with a dense mean μ and covariance P over
/// [pose; landmarks]; slot(id) is the row of landmark id (or −1).
template <class Slot>
std::vector<LandmarkEstimate> dense_landmarks(const std::vector<int>& ids, const Slot& slot,
                                              const Eigen::VectorXd& mu,
                                              const Eigen::Ref<const Eigen::MatrixXd>& P) {
  std::vector<LandmarkEstimate> out;
  for (int id : ids) {
    const int s = slot(id);
    out.push_back({id, mu.segment<2>(s), P.block<2, 2>(s, s)});
  }
  return out;
}

template <class Slot>
Eigen::MatrixXd dense_joint_covariance(const char* filter, const std::vector<int>& ids, const Slot& slot,
                                       const Eigen::Ref<const Eigen::MatrixXd>& P) {
  std::vector<int> rows = {0, 1, 2};
  for (int id : ids) {
    const int s = slot(id);
    if (s < 0) throw InputError(filter, 0, "landmark", "no landmark with id " + std::to_string(id));
    rows.push_back(s);
    rows.push_back(s + 1);
  }
  Eigen::MatrixXd C(rows.size(), rows.size());
  for (std::size_t a = 0; a < rows.size(); ++a)
    for (std::size_t b = 0; b < rows.size(); ++b) C(a, b) = P(rows[a], rows[b]);
  return C;
}

}  // namespace slamkit::filters_detail
