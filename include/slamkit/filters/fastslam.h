// FastSLAM 1.0 and 2.0 (Montemerlo et al. 2002, 2003): a Rao-Blackwellized particle filter.
// Each particle k holds a pose x_k (2.0: with the Gaussian N(x_k, Σ_k) of the motion since
// the last scan), a weight w_k and one 2×2 EKF per landmark, stored in a PersistentLandmarkMap
// so that resampling copies a pointer and an update copies O(log n) nodes: a step costs
// O(M log n) for M particles and n landmarks.
//   1.0: predict samples the control u ~ N(u, Q) and moves the particle; update weights by
//        Π N(ν; 0, S), S = H_m P H_mᵀ + R, then updates each landmark EKF (Joseph form).
//   2.0: predict moves the mean and grows Σ ← F_x Σ F_xᵀ + F_u Q F_uᵀ; update draws the pose
//        from the proposal N(μ, Σ) refined by each associated observation in turn
//        (K = Σ H_xᵀ (H_x Σ H_xᵀ + S)⁻¹, μ += K ν, Σ ← (I − K H_x) Σ), weights by
//        Π N(ν; 0, H_x Σ₀ H_xᵀ + S) at the predicted pose, then updates the landmarks from the
//        drawn pose and resets Σ = 0.
// Weights are kept as logarithms. After an update, when N_eff = 1 / Σ w² < threshold·M the
// particles are resampled (systematic, stratified or multinomial).
// Association: known ids, or per-particle gated nearest neighbour (one function,
// fastslam_associate). Under nn a new landmark's id is shared by every particle that starts
// it from the same observation, and a grid of landmark positions shared by all particles
// gives each observation its candidate ids (looked up in the particle's own map), so nn costs
// O(M k log n) too. New landmarks do not change the weights (same for every particle).
// Estimates: pose() is the weighted mean (heading: circular mean), pose_covariance() the
// weighted covariance of the mixture (heading wrapped around the mean); landmarks() and
// joint_covariance() are taken from the highest-weight particle (LandmarkSummary::kBest) or
// from the weighted mixture of all particles that hold the landmark (kMixture).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "slamkit/filters/landmark_filter.h"
#include "slamkit/filters/persistent_landmark_map.h"

namespace slamkit {

enum class ResamplingScheme { kSystematic, kStratified, kMultinomial };
/// "systematic" | "stratified" | "multinomial"; InputError otherwise.
ResamplingScheme parse_resampling_scheme(const std::string& name);
const char* resampling_scheme_name(ResamplingScheme scheme);

/// Indices of the resampled particles (size N), given normalized weights; draws from `rng`.
std::vector<int> resample_indices(const std::vector<double>& weights, ResamplingScheme scheme,
                                  std::mt19937_64& rng);

enum class FastSlamAssociation { kKnown, kNearestNeighbour };
enum class LandmarkSummary { kBest, kMixture };

struct FastSlamOptions {
  int version = 2;                  // 1 or 2
  int particles = 100;              // M
  double resample_fraction = 0.75;  // resample when N_eff < fraction · M
  ResamplingScheme resampling = ResamplingScheme::kStratified;
  FastSlamAssociation association = FastSlamAssociation::kKnown;
  double gate_distance2 = 4.0;      // nn: match when d² = νᵀ S⁻¹ ν ≤ this (Bailey's GATE_REJECT)
  double new_landmark_distance2 = 25.0;  // nn: new landmark when d² > this to every candidate
  double known_gate_distance2 = 0;  // known: > 0 rejects d² above it (outliers); 0 keeps all
  double grid_cell = 5.0;           // m, cell of the shared candidate grid (nn)
  double candidate_radius = 10.0;   // m, candidates within this of the observed position (nn)
  LandmarkSummary summary = LandmarkSummary::kBest;
  std::uint64_t seed = 1;
  Eigen::Vector3d initial_pose = Eigen::Vector3d::Zero();
  Eigen::Matrix3d initial_covariance = Eigen::Matrix3d::Zero();  // particles drawn from it
};

/// Per-particle gated nearest neighbour: for observation i, candidates[i] lists (landmark id,
/// d²). Returns per observation a landmark id, kFastSlamNew or kFastSlamRejected; each
/// landmark is matched at most once, the closest pairs first.
constexpr int kFastSlamNew = -1;
constexpr int kFastSlamRejected = -2;
std::vector<int> fastslam_associate(const std::vector<std::vector<std::pair<int, double>>>& candidates,
                                    double gate_distance2, double new_landmark_distance2);

struct FastSlamParticle {
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();
  Eigen::Matrix3d pose_covariance = Eigen::Matrix3d::Zero();  // 2.0: motion since the last scan
  double log_weight = 0;
  PersistentLandmarkMap map;
};

class FastSlam final : public LandmarkFilter {
 public:
  FastSlam(std::shared_ptr<const MotionModel> motion, const RangeBearingModel& sensor,
           const FastSlamOptions& options);

  std::string name() const override { return options_.version == 1 ? "fastslam1" : "fastslam2"; }
  void predict(const Control& u) override;
  void update(const std::vector<RangeBearing>& observations) override;
  Eigen::Vector3d pose() const override;
  Eigen::Matrix3d pose_covariance() const override;
  std::vector<LandmarkEstimate> landmarks() const override;
  Eigen::MatrixXd joint_covariance(const std::vector<int>& landmark_ids) const override;
  const UpdateStatistics& last_update() const override { return stats_; }

  /// Gives every particle the same map (one shared tree, O(M)): a known prior map, or a
  /// pre-built map of n landmarks for the scaling benchmark. Landmark ids must be >= 0.
  void set_common_map(const PersistentLandmarkMap& map);
  const std::vector<FastSlamParticle>& particles() const { return particles_; }
  /// Normalized weights (sum 1).
  std::vector<double> weights() const;
  double effective_sample_size() const;
  int resample_count() const { return resamples_; }
  int best_particle() const;

 private:
  struct Prepared;  // one observation against one particle's landmark
  void update_particle(FastSlamParticle& p, const std::vector<RangeBearing>& z,
                       const std::vector<int>& new_ids, UpdateStatistics* stats);
  std::vector<int> associate_particle(const FastSlamParticle& p, const std::vector<RangeBearing>& z,
                                      const Eigen::Matrix3d& pose_cov) const;
  Eigen::Vector3d sample_gaussian(const Eigen::Vector3d& mean, const Eigen::Matrix3d& cov);
  void register_landmark(int id, const Eigen::Vector2d& position);
  void resample_if_needed();

  std::shared_ptr<const MotionModel> motion_;
  RangeBearingModel sensor_;
  FastSlamOptions options_;
  std::vector<FastSlamParticle> particles_;
  std::mt19937_64 rng_;
  UpdateStatistics stats_;
  int resamples_ = 0;
  int next_id_ = 0;  // nn: ids of new landmarks
  std::unordered_map<std::int64_t, std::vector<int>> grid_;  // nn: cell → landmark ids
  std::unordered_map<int, bool> registered_;
};

}  // namespace slamkit
