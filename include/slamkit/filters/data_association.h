// Data association of range-bearing observations to map landmarks, shared by every filter:
// the Gaussian filters (EKF, EIF, SEIF) call associate_landmarks() with their pose, landmark
// means and joint covariance; FastSLAM calls associate() per particle with its predicted
// measurements (its innovation covariances are independent given the particle's pose, so the
// default block-diagonal joint covariance is exact there).
//
// Squared Mahalanobis distance of observation z to landmark j: d² = νᵀ S⁻¹ ν with the innovation
// ν = z − ẑ_j (bearing wrapped to (−π, π]) and S = H P Hᵀ + R.
//   known: the observation's id (id < 0 is an error); ids not in the map start a new landmark.
//   nn:    pairs with d² ≤ χ²₂(gate_probability) are matched greedily in increasing d², each
//          landmark at most once; an unmatched observation with d² ≥ new_landmark_distance2 to
//          every landmark starts a new one, otherwise it is rejected (ambiguous).
//   jcbb:  joint compatibility branch and bound (Neira & Tardós 2001): the hypothesis with the
//          most pairings whose joint D² = νᵀ S_joint⁻¹ ν ≤ χ²_{2k}(jcbb_probability), ties
//          broken by the smaller D²; unpaired observations as in nn.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "slamkit/filters/models.h"

namespace slamkit {

enum class AssociationMethod { kKnown, kNearestNeighbour, kJcbb };

/// "known" | "nn" | "jcbb"; throws InputError otherwise.
AssociationMethod parse_association_method(const std::string& name);
const char* association_method_name(AssociationMethod method);

struct AssociationOptions {
  AssociationMethod method = AssociationMethod::kKnown;
  double gate_probability = 0.99;        // individual χ²₂ gate
  double new_landmark_distance2 = 25.0;  // d² to every landmark above this: a new landmark
  double jcbb_probability = 0.99;        // joint χ²_{2k} gate
  long jcbb_max_nodes = 200000;          // search budget; the best hypothesis so far is kept
  double candidate_range = 0;            // > 0: only landmarks predicted within this range
  /// known: > 0 rejects a sighting of a mapped landmark whose d² = νᵀS⁻¹ν exceeds χ²₂(this)
  /// (misread ids, reflections); 0 accepts every sighting as given. Gaussian filters only.
  double known_gate_probability = 0;
};

/// Result codes besides a landmark id (≥ 0).
constexpr int kNewLandmark = -1;
constexpr int kRejectedObservation = -2;

/// A map landmark as the sensor would see it: predicted measurement and innovation covariance.
struct PredictedMeasurement {
  int landmark_id = -1;
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  Eigen::Matrix2d S = Eigen::Matrix2d::Identity();
};

/// Joint innovation covariance (2k × 2k) of the listed predicted measurements (indices into
/// the predicted vector, distinct). Empty function: block diagonal of their S.
using JointInnovationFn = std::function<Eigen::MatrixXd(const std::vector<int>& predicted_indices)>;

/// Gated nearest neighbour on precomputed squared Mahalanobis distances (the core of kNearestNeighbour,
/// shared with FastSLAM's per-particle association): candidates[i] lists (landmark id, d²) of
/// observation i. Pairs with d² ≤ gate_distance2 are matched closest first, each landmark at
/// most once; an unmatched observation is kNewLandmark when every candidate has
/// d² ≥ new_landmark_distance2, else kRejectedObservation.
std::vector<int> nearest_neighbour_from_distances(const std::vector<std::vector<std::pair<int, double>>>& candidates,
                                                  double gate_distance2, double new_landmark_distance2);

/// One entry per observation: a landmark id, kNewLandmark or kRejectedObservation.
/// Under kKnown, `predicted` needs only the ids of the landmarks in the map.
std::vector<int> associate(const std::vector<RangeBearing>& observations,
                           const std::vector<PredictedMeasurement>& predicted,
                           const AssociationOptions& options, const JointInnovationFn& joint = {});

/// Joint covariance of [pose; landmarks ids...] ((3 + 2k)², in the order given).
using JointCovarianceFn = std::function<Eigen::MatrixXd(const std::vector<int>& landmark_ids)>;

/// For Gaussian filters: predicts every landmark (within candidate_range), forms S from the
/// filter's joint covariance and associates. `ids` and `means` list the map.
std::vector<int> associate_landmarks(const std::vector<RangeBearing>& observations,
                                     const Eigen::Vector3d& pose, const std::vector<int>& ids,
                                     const std::vector<Eigen::Vector2d>& means,
                                     const JointCovarianceFn& covariance,
                                     const RangeBearingModel& sensor,
                                     const AssociationOptions& options);

}  // namespace slamkit
