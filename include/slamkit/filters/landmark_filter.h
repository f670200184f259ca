// The one interface of every 2D landmark-SLAM filter (EKF, EIF, SEIF, FastSLAM 1.0/2.0), so
// that the Monte-Carlo runner, the CLI and the evaluation treat them alike. State: the pose
// x = (x, y, θ) and the landmarks seen so far, each keyed by its landmark id (the true id
// under known association, the filter's own id under unknown association).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "slamkit/filters/data_association.h"
#include "slamkit/filters/models.h"

namespace slamkit {

struct LandmarkEstimate {
  int id = -1;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
};

/// What one update() did, for NIS and the association statistics.
struct UpdateStatistics {
  int observations = 0;
  int associated = 0;        // matched to a landmark already in the map
  int new_landmarks = 0;     // initialized by this update
  int rejected = 0;          // outside every gate but too close to start a new landmark
  double nis = 0;            // Σ νᵀ S⁻¹ ν over the associated observations
  int nis_dof = 0;           // 2 · associated
};

/// What every filter is built from (filter-specific fields are ignored by the others).
struct LandmarkFilterOptions {
  std::shared_ptr<const MotionModel> motion;  // required
  RangeBearingModel sensor{0.1, 1.0 * 3.14159265358979323846 / 180.0};
  Eigen::Vector3d initial_pose = Eigen::Vector3d::Zero();
  /// Standard deviations of the initial pose (> 0: the information filters need Ω₀ = P₀⁻¹).
  Eigen::Vector3d initial_sigma = Eigen::Vector3d(1e-3, 1e-3, 1e-4);
  /// Per-predict pose noise added to F_u Q F_uᵀ (rank 2 for a 2-D control): makes the motion
  /// noise invertible, which the information form's augment-then-marginalize step needs.
  /// Every filter adds it, so they all run the same model. The default adds ~2% (x, y) and
  /// ~1% (θ) to the Bailey simulator's per-step motion variance.
  Eigen::Vector3d pose_noise_floor = Eigen::Vector3d(1e-3, 1e-3, 1e-4);
  AssociationOptions association;
  int active_landmarks = 6;  // SEIF: bound on the active set
  int particles = 100;       // FastSLAM
  /// Capacity hint for the dense filters (EKF): storage for this many landmarks is allocated
  /// up front, so the n × n covariance is not regrown while the map fills (0: grow by 1.5×).
  int expected_landmarks = 0;
  std::uint64_t seed = 1;    // particle filters
};

class LandmarkFilter {
 public:
  virtual ~LandmarkFilter() = default;
  virtual std::string name() const = 0;
  /// Motion update with one control.
  virtual void predict(const Control& u) = 0;
  /// Measurement update with every observation of one sensor scan.
  virtual void update(const std::vector<RangeBearing>& observations) = 0;
  /// Current pose estimate (θ wrapped) and its 3×3 marginal covariance.
  virtual Eigen::Vector3d pose() const = 0;
  virtual Eigen::Matrix3d pose_covariance() const = 0;
  /// Every landmark in the map with its mean and 2×2 marginal covariance.
  virtual std::vector<LandmarkEstimate> landmarks() const = 0;
  /// Joint covariance of [pose; landmark ids...] (3 + 2k square), any block of the state.
  virtual Eigen::MatrixXd joint_covariance(const std::vector<int>& landmark_ids) const = 0;
  virtual const UpdateStatistics& last_update() const = 0;
};

}  // namespace slamkit
