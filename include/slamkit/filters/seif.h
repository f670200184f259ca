// Sparse extended information filter SLAM (Thrun et al. 2004) with a pluggable rule for the
// landmark that becomes passive: the standard SEIF rule or P2's entropy rule.
//
// Storage: (Ω, ξ, μ) in blocks — the 3×3 pose block, per landmark its 2×2 diagonal block, its
// pose link Ω_xm (non-zero only while active) and a short list of landmark–landmark links. No
// n × n matrix exists; every step touches only the pose, the ≤ A active landmarks, the
// landmarks observed and a fixed number of others, so its time does not grow with the map.
//   predict: augment-then-marginalize restricted to {x} ∪ active (the old pose's Markov
//            blanket; nothing else changes) — fill-in only among active landmarks.
//   update:  Ω += Hᵀ R⁻¹ H, ξ += Hᵀ R⁻¹ (ν + H μ) per observation (pose and one landmark, which
//            becomes active); new landmarks enter by the factor of the EKF's initialization.
//   sparsify when |active| > A: split active into m⁺ (kept) and m⁰ (made passive) by the rule,
//            Ω̃ = Ω¹ − Ω² + Ω³, ξ̃ = ξ + (Ω̃ − Ω) μ with, on L = {x} ∪ m⁺ ∪ m⁰ (Ω⁰ = Ω_LL):
//              Ω¹ = Ω⁰ − Ω⁰_{·m⁰} (Ω⁰_{m⁰m⁰})⁻¹ Ω⁰_{m⁰·}      (p(x, m⁺ | m⁻ = 0))
//              Ω² = Ω⁰ − Ω⁰_{·(x,m⁰)} (Ω⁰_{(x,m⁰)(x,m⁰)})⁻¹ Ω⁰_{(x,m⁰)·}   (p(m⁺ | m⁻ = 0))
//              Ω³ = Ω − Ω_{·x} Ω_xx⁻¹ Ω_{x·}                    (p(m))
//            so p(x, m) ≈ p(x | m⁺, m⁻ = 0) p(m): the pose loses its links to m⁰.
//   mean:    amortized recovery, `recovery_sweeps` block Gauss–Seidel (coordinate descent on
//            ½ μᵀΩμ − ξᵀμ) sweeps over the pose, the active landmarks and `recovery_extra`
//            further landmarks in round-robin order: μ_i ← Ω_ii⁻¹ (ξ_i − Σ_{j≠i} Ω_ij μ_j).
// With A ≥ the number of landmarks nothing is sparsified and SEIF equals the EIF (tested).
//
// Covariances: association and the entropy rule use the local covariance (Ω_LL)⁻¹ over the
// pose, the active landmarks and the queried ones with their neighbours (conditional on the
// rest, Thrun's approximation; constant time). The evaluation accessors (pose_covariance,
// joint_covariance, landmarks) are exact marginals from a sparse LDLᵀ of Ω (O(n) to O(n^1.5)
// per call; not part of a filter step), landmarks() falls back to the conditional Ω_ii⁻¹
// above exact_marginals_limit landmarks.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <unordered_map>
#include <vector>

#include "slamkit/filters/landmark_filter.h"

namespace slamkit {

/// P2's entropy rule. Score of active landmark m_i: S(m_i) = H(x_t | m_i) + H(x_{t+1} | m_i);
/// the landmarks with the LARGEST score (the weakest links to the pose) become passive.
/// H(x_{t+1} | m_i) is the unconditional H(x_{t+1}) (its maximum) when m_i is not observed at
/// t+1 (eq. 14). Landmarks without a time-t value (new, or re-activated) compete as P2's
/// reference candidates (eq. 15, see NewLandmarkScore). The four cases of P2 (new landmark seen
/// or not × all or part of the time-t active set seen again) all reduce to this one score.
struct EntropyRuleOptions {
  enum class NewLandmarkScore {
    kPoseEntropy,   // H(x_t | m) := H(x_t), the unconditional (maximal) value
    kCurrentTwice,  // S = 2 H(x_{t+1} | m)
    kKeepActive,    // new landmarks never compete: only time-t active ones become passive
  };
  NewLandmarkScore new_landmarks = NewLandmarkScore::kPoseEntropy;
  bool use_previous_step = true;  // false: S = H(x_{t+1} | m_i) alone
};

enum class SparsificationRule {
  kStandard,  // Thrun 2004: keep the A most recently observed (ties: later in the scan kept)
  kEntropy,   // P2
};

struct SeifOptions {
  SparsificationRule rule = SparsificationRule::kStandard;
  EntropyRuleOptions entropy;
  int recovery_sweeps = 2;
  int recovery_extra = 20;
  int exact_marginals_limit = 2000;
};

class Seif final : public LandmarkFilter {
 public:
  Seif(LandmarkFilterOptions options, SeifOptions seif = {});
  ~Seif() override;
  std::string name() const override;
  void predict(const Control& u) override;
  void update(const std::vector<RangeBearing>& observations) override;
  Eigen::Vector3d pose() const override;
  Eigen::Matrix3d pose_covariance() const override;
  std::vector<LandmarkEstimate> landmarks() const override;
  Eigen::MatrixXd joint_covariance(const std::vector<int>& landmark_ids) const override;
  const UpdateStatistics& last_update() const override { return stats_; }

  int active_count() const { return int(active_.size()); }
  bool is_active(int id) const;
  std::size_t size() const;
  /// Largest number of landmark–landmark links of any landmark (bounded fill-in).
  int max_links() const;
  /// Ids of the landmarks linked to landmark `id` in Ω.
  std::vector<int> linked_landmarks(int id) const;
  /// Runs `sweeps` Gauss–Seidel sweeps over every variable (for tests and final maps).
  void recover_mean_fully(int sweeps);

 private:
  struct Landmark;
  struct Factorization;
  Eigen::Matrix2d& link(int i, int j);  // creates a zero block when absent
  const Eigen::Matrix2d* find_link(int i, int j) const;
  void assemble(const std::vector<int>& set, Eigen::MatrixXd* Om, Eigen::VectorXd* xi, Eigen::VectorXd* mu) const;
  void store(const std::vector<int>& set, const Eigen::MatrixXd& Om, const Eigen::VectorXd& xi);
  // [pose; ids] from (Ω_LL)⁻¹, L = pose, active, ids (and their neighbours if asked).
  Eigen::MatrixXd local_covariance(const std::vector<int>& ids, bool with_neighbours) const;
  void sparsify();
  void remember_entropies();
  std::vector<int> choose_passive(const Eigen::MatrixXd& Sigma_local) const;
  void recover_mean(const std::vector<int>& extra_first);
  void gauss_seidel_pose();
  void gauss_seidel_landmark(int k);
  const Factorization& factorization() const;

  LandmarkFilterOptions o_;
  SeifOptions s_;
  Eigen::Vector3d mu_x_, xi_x_;
  Eigen::Matrix3d omega_xx_;
  std::vector<Landmark> lm_;
  std::vector<int> active_;              // landmark indices with a pose link
  std::unordered_map<int, int> index_;   // id → landmark index
  long scan_ = 0;
  std::size_t round_robin_ = 0;
  int next_id_ = 0;
  double pose_entropy_prev_ = 0;         // H(x_t) of the previous scan
  std::vector<int> observed_now_;        // landmark indices observed in this scan (in order)
  UpdateStatistics stats_;
  mutable std::unique_ptr<Factorization> factor_;
};

}  // namespace slamkit
