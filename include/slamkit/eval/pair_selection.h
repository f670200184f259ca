// Selection of the index pairs (i, j) over which the relative pose error is computed, with
// evo's definitions (evo/core/filters.py) for frames, metres and angles; seconds are ours.
//   frames   consecutive: i, j = i + δ on the grid 0, δ, 2δ, …;  all pairs: every (i, i + δ).
//   metres   path length d_k = Σ_{m<k} ‖p_{m+1} − p_m‖.
//            consecutive (evo): accumulate the path from sample 0 and restart it whenever it
//            reaches δ; the samples where it does form the chain, so the first chain sample is
//            the first one ≥ δ from sample 0 (sample 0 itself is not used), pairs join
//            neighbours in the chain.  all pairs: for every i the first j > i minimizing
//            |d_j − d_i − δ|, kept if that is ≤ tol.
//   degrees, radians  (δ ≤ 180° or π)  consecutive: accumulate the angles ‖Log(R_k⁻¹ R_{k+1})‖
//            from a chain start (sample 0 first); when the sum reaches δ at sample j, (start, j)
//            is a pair and j the next start.  all pairs: every (i, j > i) with
//            | ‖Log(R_i⁻¹ R_j)‖ − δ | ≤ tol (O(n²)).
//   seconds  consecutive: from a start s (sample 0 first), the first j with t_j − t_s ≥ δ
//            closes the pair (s, j) and starts the next.  all pairs: as metres with d = t.
// tol = rel_tol · δ (evo's rel_delta_tol, default 0.1).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "slamkit/core/trajectory.h"

namespace slamkit {

enum class DeltaUnit { kFrames, kMeters, kDegrees, kRadians, kSeconds };

/// "f", "m", "d", "r", "s" (evo's --delta_unit letters).
const char* to_string(DeltaUnit unit);
/// "frames", "meters", …, for messages.
const char* long_name(DeltaUnit unit);
/// Accepts the letters and the long names; throws InputError (field "delta-unit").
DeltaUnit parse_delta_unit(std::string_view name);

using IndexPairs = std::vector<std::pair<std::size_t, std::size_t>>;

/// The pairs of `traj` for a step δ; throws slamkit::Error for an invalid δ (not positive,
/// not an integer number of frames, an angle beyond 180°, seconds without timestamps) or
/// when no pair is found.
IndexPairs select_pairs(const Trajectory& traj, double delta, DeltaUnit unit, bool all_pairs,
                        double rel_tol = 0.1);

}  // namespace slamkit
