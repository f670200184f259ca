#include "slamkit/eval/evaluation.h"

#include <stdexcept>

#include "slamkit/core/error.h"

namespace slamkit {

const char* to_string(MetricKind kind) { return kind == MetricKind::kAte ? "ate" : "rpe"; }

namespace {
ErrorStatistics stats_of(const std::vector<double>& e, const char* what) {
  try {
    return compute_statistics(e);
  } catch (const std::invalid_argument& ex) {
    throw Error(std::string(what) + ": " + ex.what());
  }
}
}  // namespace

EvalResult evaluate(const Trajectory& est, const Trajectory& ref, const EvalOptions& options) {
  EvalResult r;
  r.options = options;
  r.options.rpe.relation = options.relation;
  r.association = associate(est, ref, options.association);
  const Trajectory est_matched = est.subset(r.association.est_ids);
  r.ref = ref.subset(r.association.ref_ids);
  r.alignment = compute_alignment(est_matched, r.ref, options.align, options.n_align);
  r.est = apply_alignment(est_matched, r.alignment);

  if (options.kind == MetricKind::kAte) {
    r.errors = compute_ate(r.est, r.ref, options.relation);
    for (std::size_t k = 0; k < r.est.size(); ++k) r.error_index.push_back(k);
  } else {
    RpeErrors rpe = compute_rpe(r.est, r.ref, r.options.rpe);
    r.pairs = std::move(rpe.pairs);
    r.errors = static_cast<PoseErrors&&>(rpe);
    for (const auto& pair : r.pairs) r.error_index.push_back(pair.second);
  }
  r.stats = stats_of(r.errors.errors, "errors");
  r.translation_stats = stats_of(r.errors.translation, "translation errors");
  r.rotation_stats = stats_of(r.errors.rotation_deg, "rotation errors");
  return r;
}

}  // namespace slamkit
