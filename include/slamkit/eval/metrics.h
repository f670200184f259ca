// Absolute and relative pose errors, as evo defines them (evo/core/metrics.py).
//
// Both take ASSOCIATED trajectories (sample k of est ↔ sample k of ref), the estimate already
// aligned. Each also reports the two standard parts for every pair, whatever the chosen
// relation: translation ‖t(E)‖ [m] and rotation angle ‖Log R(E)‖ [deg].
//   ATE/APE (Kümmerle et al.):  E_k = P_k⁻¹ Q_k (P estimate, Q reference); the translation part
//            is ‖p_est,k − p_ref,k‖ (= ‖t(E_k)‖).
//   RPE (Sturm et al., TUM RGB-D):  for a pair (i, j),
//            E_ij = (Q_i⁻¹ Q_j)⁻¹ (P_i⁻¹ P_j);  pairs from select_pairs() on the ESTIMATE
//            (evo's default) or on the reference (pairs_from_reference).
#pragma once

#include <vector>

#include "slamkit/core/trajectory.h"
#include "slamkit/eval/pair_selection.h"
#include "slamkit/eval/pose_relation.h"

namespace slamkit {

/// Per-pair errors of one metric.
struct PoseErrors {
  std::vector<double> errors;        ///< the chosen relation
  std::vector<double> translation;   ///< ‖t(E)‖ [m]
  std::vector<double> rotation_deg;  ///< ‖Log R(E)‖ [deg]
};

/// One error per sample. Throws slamkit::Error if the lengths differ or are zero.
PoseErrors compute_ate(const Trajectory& est, const Trajectory& ref, PoseRelation relation);

struct RpeOptions {
  double delta = 1.0;
  DeltaUnit delta_unit = DeltaUnit::kFrames;
  double rel_tol = 0.1;               ///< tolerance of all-pairs matching, relative to delta
  bool all_pairs = false;
  bool pairs_from_reference = false;
  PoseRelation relation = PoseRelation::kTranslation;
};

struct RpeErrors : PoseErrors {
  IndexPairs pairs;  ///< errors[k] belongs to pairs[k]
};

/// Throws slamkit::Error if the lengths differ or no pair is found.
RpeErrors compute_rpe(const Trajectory& est, const Trajectory& ref, const RpeOptions& options);

}  // namespace slamkit
