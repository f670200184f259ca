// The evaluation pipeline behind `slamkit eval ate|rpe`, in evo's order:
//   associate (timestamps or index) → align the estimate (alignment.h) → errors (metrics.h)
//   → statistics of the chosen relation and of the translation / rotation parts.
#pragma once

#include <cstddef>
#include <vector>

#include "slamkit/core/trajectory.h"
#include "slamkit/eval/alignment.h"
#include "slamkit/eval/association.h"
#include "slamkit/eval/metrics.h"
#include "slamkit/eval/statistics.h"

namespace slamkit {

enum class MetricKind { kAte, kRpe };
/// "ate" / "rpe"
const char* to_string(MetricKind kind);

struct EvalOptions {
  MetricKind kind = MetricKind::kAte;
  AssociationOptions association;
  AlignmentMode align = AlignmentMode::kNone;
  std::size_t n_align = 0;  ///< use only the first n associated pairs for the alignment (0: all)
  PoseRelation relation = PoseRelation::kTranslation;
  RpeOptions rpe;           ///< RPE only; its `relation` is overridden by `relation`
};

struct EvalResult {
  EvalOptions options;
  Association association;
  Similarity3 alignment;                 ///< applied to the estimate
  Trajectory est;                        ///< associated and aligned estimate
  Trajectory ref;                        ///< associated reference (same length as est)
  PoseErrors errors;
  IndexPairs pairs;                      ///< RPE only
  std::vector<std::size_t> error_index;  ///< sample of est/ref each error is drawn at (k, or j of (i, j))
  ErrorStatistics stats;                 ///< of errors.errors
  ErrorStatistics translation_stats;     ///< of errors.translation [m]
  ErrorStatistics rotation_stats;        ///< of errors.rotation_deg [deg]
};

/// Runs the pipeline; throws slamkit::Error (or InputError) on unusable input.
EvalResult evaluate(const Trajectory& est, const Trajectory& ref, const EvalOptions& options);

}  // namespace slamkit
