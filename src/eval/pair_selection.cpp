#include "slamkit/eval/pair_selection.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {

namespace {

IndexPairs chain_to_pairs(const std::vector<std::size_t>& chain) {
  IndexPairs pairs;
  for (std::size_t k = 1; k < chain.size(); ++k) pairs.emplace_back(chain[k - 1], chain[k]);
  return pairs;
}

IndexPairs by_frames(std::size_t n, std::size_t delta, bool all_pairs) {
  IndexPairs pairs;
  if (all_pairs) {
    for (std::size_t i = 0; i + delta < n; ++i) pairs.emplace_back(i, i + delta);
    return pairs;
  }
  for (std::size_t i = 0; i + delta < n; i += delta) pairs.emplace_back(i, i + delta);
  return pairs;
}

/// All pairs on a non-decreasing scalar d (path length or time): for each i the first
/// j > i minimizing |(d_j − d_i) − δ|, kept if ≤ tol.
IndexPairs all_pairs_on_scale(const std::vector<double>& d, double delta, double tol) {
  IndexPairs pairs;
  const std::size_t n = d.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    auto v = [&](std::size_t j) { return (d[j] - d[i]) - delta; };
    // first j > i with v(j) ≥ 0 (v is non-decreasing in j)
    std::size_t lo = i + 1, hi = n;
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (v(mid) < 0.0) lo = mid + 1; else hi = mid;
    }
    const std::size_t k = lo;
    std::size_t best = n;
    double best_abs = 0.0;
    if (k > i + 1) {
      const double target = v(k - 1);  // largest negative value; take its first occurrence
      std::size_t a = i + 1, b = k - 1;
      while (a < b) {
        const std::size_t mid = a + (b - a) / 2;
        if (v(mid) < target) a = mid + 1; else b = mid;
      }
      best = a;
      best_abs = -target;
    }
    if (k < n && (best == n || std::abs(v(k)) < best_abs)) {
      best = k;
      best_abs = std::abs(v(k));
    }
    if (best < n && best_abs <= tol) pairs.emplace_back(i, best);
  }
  return pairs;
}

IndexPairs by_path(const std::vector<Eigen::Vector3d>& p, double delta, double tol, bool all_pairs) {
  if (all_pairs) {
    std::vector<double> d(p.size(), 0.0);
    for (std::size_t k = 1; k < p.size(); ++k) d[k] = d[k - 1] + (p[k - 1] - p[k]).norm();
    return all_pairs_on_scale(d, delta, tol);
  }
  std::vector<std::size_t> chain;
  double path = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (k > 0) path += (p[k] - p[k - 1]).norm();
    if (path >= delta) {
      chain.push_back(k);
      path = 0.0;
    }
  }
  return chain_to_pairs(chain);
}

/// ‖Log(Aᵀ B)‖ on the rotation matrices as read (see TrajectorySample::source_rotation).
double relative_angle(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return SO3::from_matrix(A.transpose() * B).log().norm();
}

IndexPairs by_angle(const Trajectory& traj, double delta_rad, double tol_rad, bool all_pairs) {
  IndexPairs pairs;
  const std::size_t n = traj.size();
  std::vector<Eigen::Matrix3d> R;
  R.reserve(n);
  for (const auto& s : traj) R.push_back(s.rotation_matrix());
  if (all_pairs) {
    // O(n²): the angle from the trace, tr(Rᵢᵀ Rⱼ) = Σ Rᵢ ∘ Rⱼ, accurate away from 0 and π,
    // and exact enough to compare with a tolerance band.
    for (std::size_t i = 0; i + 1 < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        const double c = std::clamp(0.5 * (R[i].cwiseProduct(R[j]).sum() - 1.0), -1.0, 1.0);
        if (std::abs(std::acos(c) - delta_rad) <= tol_rad) pairs.emplace_back(i, j);
      }
    }
    return pairs;
  }
  double acc = 0.0;
  std::size_t start = 0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    acc += relative_angle(R[k], R[k + 1]);
    if (acc >= delta_rad) {
      pairs.emplace_back(start, k + 1);
      acc = 0.0;
      start = k + 1;
    }
  }
  return pairs;
}

IndexPairs by_time(const std::vector<double>& t, double delta, double tol, bool all_pairs) {
  if (all_pairs) return all_pairs_on_scale(t, delta, tol);
  IndexPairs pairs;
  std::size_t start = 0;
  for (std::size_t j = 1; j < t.size(); ++j) {
    if (t[j] - t[start] >= delta) {
      pairs.emplace_back(start, j);
      start = j;
    }
  }
  return pairs;
}

}  // namespace

const char* to_string(DeltaUnit unit) {
  switch (unit) {
    case DeltaUnit::kFrames: return "f";
    case DeltaUnit::kMeters: return "m";
    case DeltaUnit::kDegrees: return "d";
    case DeltaUnit::kRadians: return "r";
    case DeltaUnit::kSeconds: return "s";
  }
  return "?";
}

const char* long_name(DeltaUnit unit) {
  switch (unit) {
    case DeltaUnit::kFrames: return "frames";
    case DeltaUnit::kMeters: return "meters";
    case DeltaUnit::kDegrees: return "degrees";
    case DeltaUnit::kRadians: return "radians";
    case DeltaUnit::kSeconds: return "seconds";
  }
  return "?";
}

DeltaUnit parse_delta_unit(std::string_view name) {
  if (name == "f" || name == "frames") return DeltaUnit::kFrames;
  if (name == "m" || name == "meters" || name == "metres") return DeltaUnit::kMeters;
  if (name == "d" || name == "deg" || name == "degrees") return DeltaUnit::kDegrees;
  if (name == "r" || name == "rad" || name == "radians") return DeltaUnit::kRadians;
  if (name == "s" || name == "seconds") return DeltaUnit::kSeconds;
  throw InputError("", 0, "delta-unit", "unknown delta unit '" + std::string(name) + "' (expected f, m, d, r or s)");
}

IndexPairs select_pairs(const Trajectory& traj, double delta, DeltaUnit unit, bool all_pairs, double rel_tol) {
  std::ostringstream what;
  what << "delta = " << delta << " (" << long_name(unit) << ")";
  if (!std::isfinite(delta) || delta <= 0.0) throw Error(what.str() + ": delta must be positive");
  if (!std::isfinite(rel_tol) || rel_tol < 0.0) throw Error("relative delta tolerance must be non-negative");
  const double tol = delta * rel_tol;
  IndexPairs pairs;
  switch (unit) {
    case DeltaUnit::kFrames:
      if (delta != std::floor(delta)) throw Error(what.str() + ": delta must be an integer number of frames");
      pairs = by_frames(traj.size(), static_cast<std::size_t>(std::min(delta, 1e15)), all_pairs);
      break;
    case DeltaUnit::kMeters: pairs = by_path(traj.positions(), delta, tol, all_pairs); break;
    case DeltaUnit::kDegrees:
    case DeltaUnit::kRadians: {
      const double to_rad = unit == DeltaUnit::kDegrees ? kPi / 180.0 : 1.0;
      if (delta * to_rad > kPi * (1.0 + 1e-12)) throw Error(what.str() + ": a rotation angle is at most 180 degrees");
      pairs = by_angle(traj, delta * to_rad, tol * to_rad, all_pairs);
      break;
    }
    case DeltaUnit::kSeconds:
      if (!traj.has_timestamps()) throw Error(what.str() + ": the trajectory has no timestamps (e.g. KITTI)");
      pairs = by_time(traj.stamps(), delta, tol, all_pairs);
      break;
  }
  if (pairs.empty()) throw Error(what.str() + " produced no pairs; try a smaller delta or a larger tolerance");
  return pairs;
}

}  // namespace slamkit
