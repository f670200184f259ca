// Association of an estimated and a reference trajectory: which samples are compared.
//
// With timestamps on both sides this is evo's rule (sync.associate_trajectories): iterate
// over the trajectory with FEWER samples (the estimate when both have equally many); for
// each of its stamps s, take the sample of the other trajectory whose stamp, shifted by the
// offset, is nearest (the first one on ties); keep the pair if |Δt| ≤ max_diff. The offset
// is added to the estimate's stamps (t_est + offset ≈ t_ref). Several samples of the shorter
// trajectory may match the same sample of the longer one, as in evo. Unequal rates and gaps
// are handled: samples whose nearest partner is farther than max_diff are dropped.
// Without timestamps on either side (KITTI) samples are matched by index, and both
// trajectories must have the same length. Pure functions.
#pragma once

#include <cstddef>
#include <vector>

#include "slamkit/core/trajectory.h"

namespace slamkit {

struct AssociationOptions {
  double max_diff = 0.01;  ///< [s] largest accepted |t_est + offset − t_ref| (evo's default)
  double offset = 0.0;     ///< [s] added to the estimate's stamps
};

struct Association {
  std::vector<std::size_t> est_ids;  ///< est_ids[k] is matched with ref_ids[k]; both non-decreasing
  std::vector<std::size_t> ref_ids;
  bool by_index = false;             ///< true when matched by index (no timestamps)
  std::size_t size() const { return est_ids.size(); }
};

/// Throws slamkit::Error when nothing matches or index matching sees different lengths.
Association associate(const Trajectory& est, const Trajectory& ref, const AssociationOptions& options);

}  // namespace slamkit
