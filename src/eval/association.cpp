#include "slamkit/eval/association.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {

namespace {

/// For each s in queries, the first index of the nearest value in `sorted` if within max_diff.
void match_nearest(const std::vector<double>& queries, const std::vector<double>& sorted, double max_diff,
                   std::vector<std::size_t>& query_ids, std::vector<std::size_t>& sorted_ids) {
  for (std::size_t q = 0; q < queries.size(); ++q) {
    const double s = queries[q];
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), s);  // first value ≥ s
    std::size_t best = sorted.size();
    double best_diff = 0.0;
    if (it != sorted.begin()) {
      // The value just below s; its FIRST occurrence (argmin returns the first minimum).
      const double below = *(it - 1);
      best = static_cast<std::size_t>(std::lower_bound(sorted.begin(), it, below) - sorted.begin());
      best_diff = std::abs(below - s);
    }
    if (it != sorted.end()) {
      const double d = std::abs(*it - s);
      if (best == sorted.size() || d < best_diff) {
        best = static_cast<std::size_t>(it - sorted.begin());
        best_diff = d;
      }
    }
    if (best < sorted.size() && best_diff <= max_diff) {
      query_ids.push_back(q);
      sorted_ids.push_back(best);
    }
  }
}

}  // namespace

Association associate(const Trajectory& est, const Trajectory& ref, const AssociationOptions& options) {
  if (est.empty() || ref.empty()) throw Error("association: a trajectory is empty");
  if (!std::isfinite(options.max_diff) || options.max_diff < 0.0 || !std::isfinite(options.offset))
    throw Error("association: max_diff must be finite and non-negative, offset finite");
  Association a;
  if (!est.has_timestamps() || !ref.has_timestamps()) {
    if (est.size() != ref.size()) {
      std::ostringstream os;
      os << "association by index (a trajectory has no timestamps, e.g. KITTI) needs equal lengths; estimate has "
         << est.size() << " poses, reference " << ref.size();
      throw Error(os.str());
    }
    a.by_index = true;
    for (std::size_t i = 0; i < est.size(); ++i) {
      a.est_ids.push_back(i);
      a.ref_ids.push_back(i);
    }
    return a;
  }
  // evo: the longer trajectory's stamps are shifted (+offset if it is the estimate, −offset if
  // it is the reference) and searched for each stamp of the shorter one.
  const bool est_longer = est.size() > ref.size();
  const Trajectory& shorter = est_longer ? ref : est;
  const Trajectory& longer = est_longer ? est : ref;
  const double shift = est_longer ? options.offset : -options.offset;
  std::vector<double> long_stamps = longer.stamps();
  for (double& t : long_stamps) t += shift;
  std::vector<std::size_t> short_ids, long_ids;
  match_nearest(shorter.stamps(), long_stamps, options.max_diff, short_ids, long_ids);
  if (short_ids.empty()) {
    std::ostringstream os;
    os << "association: no matching timestamps between estimate (" << est.size() << " poses, "
       << est[0].stamp << " .. " << est[est.size() - 1].stamp << " s) and reference (" << ref.size() << " poses, "
       << ref[0].stamp << " .. " << ref[ref.size() - 1].stamp << " s) with max. difference " << options.max_diff
       << " s and offset " << options.offset << " s";
    throw Error(os.str());
  }
  a.est_ids = est_longer ? long_ids : short_ids;
  a.ref_ids = est_longer ? short_ids : long_ids;
  return a;
}

}  // namespace slamkit
