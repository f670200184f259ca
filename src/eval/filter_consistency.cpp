#include "slamkit/eval/filter_consistency.h"

#include <Eigen/Cholesky>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include "slamkit/core/error.h"
#include "slamkit/core/parallel.h"
#include "slamkit/filters/chi_square.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {

FilterRunResult run_filter_on_simulation(LandmarkFilter* f, const LandmarkSimRun& run, const LandmarkSimOptions& sim,
                                         const std::vector<Eigen::Vector2d>& landmarks,
                                         const FilterRunOptions& options) {
  using clock = std::chrono::steady_clock;
  FilterRunResult r;
  int map_size = 0;
  for (std::size_t k = 0; k < run.steps.size(); ++k) {
    const LandmarkSimStep& s = run.steps[k];
    const auto t0 = clock::now();
    f->predict(Control{s.v, s.steer, sim.dt});
    if (s.observed) f->update(s.observations);
    r.step_ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    if (s.observed) map_size += f->last_update().new_landmarks;
    r.step_landmarks.push_back(map_size);
    if (!s.observed) continue;
    r.nis_sum += f->last_update().nis;
    r.nis_dof += f->last_update().nis_dof;
    if (!options.evaluate) continue;
    const Eigen::Vector3d x = f->pose();
    const Eigen::Matrix3d P = f->pose_covariance();
    Eigen::Vector3d e = x - s.true_pose;
    e.z() = wrap_angle(e.z());
    const double nees = e.dot(P.ldlt().solve(e));
    if (!x.allFinite() || !P.allFinite() || !std::isfinite(nees)) r.finite = false;
    r.time.push_back((k + 1) * sim.dt);
    r.truth.push_back(s.true_pose);
    r.estimate.push_back(x);
    r.covariance.push_back(P);
    r.nees.push_back(nees);
    r.landmarks.push_back(map_size);
  }
  if (options.final_map) {
    r.final_map = f->landmarks();
    if (options.map_nees && !r.final_map.empty()) {
      double sum = 0;
      int n = 0;
      for (const auto& m : r.final_map) {
        if (m.id < 0 || m.id >= int(landmarks.size())) continue;
        const Eigen::Vector2d e = m.mean - landmarks[m.id];
        sum += e.dot(m.covariance.ldlt().solve(e));
        ++n;
        if (!m.mean.allFinite() || !m.covariance.allFinite()) r.finite = false;
      }
      if (n > 0) r.map_nees = sum / n;
    }
  }
  return r;
}

std::vector<FilterRunResult> run_monte_carlo(const FilterMaker& make, const std::vector<Eigen::Vector2d>& landmarks,
                                             const std::vector<Eigen::Vector2d>& waypoints,
                                             const LandmarkSimOptions& sim, const MonteCarloOptions& o) {
  if (o.runs < 1) throw InputError("--runs", 0, "runs", "need at least one run");
  std::vector<FilterRunResult> results(o.runs);
  ThreadPool pool(o.threads);
  std::mutex progress_mutex;
  int done = 0;
  pool.parallel_for(
      std::size_t(o.runs),
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const std::uint64_t seed = o.first_seed + i;
          const LandmarkSimRun run = simulate_landmark_run(landmarks, waypoints, sim, seed);
          std::unique_ptr<LandmarkFilter> f = make();
          results[i] = run_filter_on_simulation(f.get(), run, sim, landmarks, o.run);
          results[i].seed = seed;
          std::lock_guard<std::mutex> lock(progress_mutex);
          ++done;
          if (o.progress) o.progress(done, o.runs);
        }
      },
      1);
  return results;
}

ConsistencySummary summarize_consistency(const std::vector<FilterRunResult>& runs, double confidence) {
  ConsistencySummary s;
  s.runs = int(runs.size());
  s.confidence = confidence;
  if (runs.empty()) throw InputError("monte carlo", 0, "runs", "no runs to summarize");
  const std::size_t T = runs.front().nees.size();
  for (const auto& r : runs)
    if (r.nees.size() != T) throw InputError("monte carlo", 0, "runs", "runs differ in length");
  const double N = double(runs.size());
  s.anees_lo = chi2_quantile(0.5 * (1 - confidence), 3 * N) / N;
  s.anees_hi = chi2_quantile(1 - 0.5 * (1 - confidence), 3 * N) / N;
  double sq_pos = 0, sq_head = 0, nis = 0, dof = 0, map = 0, steps = 0, sum_ms = 0, lm = 0;
  int inside = 0, map_runs = 0;
  s.time = T > 0 ? runs.front().time : std::vector<double>{};
  for (std::size_t k = 0; k < T; ++k) {
    double a = 0, p = 0, h = 0;
    for (const auto& r : runs) {
      a += r.nees[k];
      const Eigen::Vector3d e = r.estimate[k] - r.truth[k];
      p += e.head<2>().squaredNorm();
      h += std::pow(wrap_angle(e.z()), 2);
    }
    s.anees.push_back(a / N);
    s.rmse_position.push_back(std::sqrt(p / N));
    s.rmse_heading.push_back(std::sqrt(h / N));
    sq_pos += p;
    sq_head += h;
    inside += (a / N >= s.anees_lo && a / N <= s.anees_hi);
    s.anees_mean += a / N / T;
  }
  for (const auto& r : runs) {
    nis += r.nis_sum;
    dof += double(r.nis_dof);
    if (std::isfinite(r.map_nees)) map += r.map_nees, ++map_runs;
    for (double ms : r.step_ms) sum_ms += ms, s.time_per_step_max_ms = std::max(s.time_per_step_max_ms, ms);
    steps += double(r.step_ms.size());
    lm += double(r.final_map.size());
    s.finite = s.finite && r.finite;
  }
  if (T > 0) {
    s.fraction_in_bounds = double(inside) / T;
    s.rmse_position_total = std::sqrt(sq_pos / (N * T));
    s.rmse_heading_total = std::sqrt(sq_head / (N * T));
  }
  s.anis = dof > 0 ? nis / dof : std::numeric_limits<double>::quiet_NaN();
  if (map_runs > 0) s.map_nees = map / map_runs;
  s.time_per_step_mean_ms = steps > 0 ? sum_ms / steps : 0;
  s.landmarks = int(std::lround(lm / N));
  return s;
}

}  // namespace slamkit
