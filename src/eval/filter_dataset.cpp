#include "slamkit/eval/filter_dataset.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <ctime>

#include "slamkit/core/error.h"
#include "slamkit/eval/filter_plots.h"
#include "slamkit/eval/plot.h"
#include "slamkit/filters/victoria_park_model.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {

namespace {

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

bool has_truth(const LandmarkDataset& ds) { return !ds.truth_times.empty(); }

// Least-squares R, t of ref ≈ R est + t (Kabsch in 2-D).
void align_2d(const std::vector<Eigen::Vector2d>& est, const std::vector<Eigen::Vector2d>& ref, Eigen::Matrix2d* R,
              Eigen::Vector2d* t) {
  Eigen::Vector2d me = Eigen::Vector2d::Zero(), mr = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < est.size(); ++k) me += est[k], mr += ref[k];
  me /= double(est.size()), mr /= double(ref.size());
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (std::size_t k = 0; k < est.size(); ++k) C += (ref[k] - mr) * (est[k] - me).transpose();
  Eigen::JacobiSVD<Eigen::Matrix2d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d D = Eigen::Matrix2d::Identity();
  D(1, 1) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  *R = svd.matrixU() * D * svd.matrixV().transpose();
  *t = mr - *R * me;
}

// GPS fixes matched to the nearest scan within 0.25 s: (scan index, fix index).
std::vector<std::pair<std::size_t, std::size_t>> match_gps(const std::vector<double>& scan_times,
                                                           const LandmarkDataset& ds) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t k = 0; k < ds.gps_times.size(); ++k) {
    auto it = std::lower_bound(scan_times.begin(), scan_times.end(), ds.gps_times[k]);
    std::size_t j = static_cast<std::size_t>(it - scan_times.begin());
    if (j > 0 && (j == scan_times.size() || ds.gps_times[k] - scan_times[j - 1] < scan_times[j] - ds.gps_times[k])) --j;
    if (j >= scan_times.size() || std::abs(scan_times[j] - ds.gps_times[k]) > 0.25) continue;
    out.emplace_back(j, k);
  }
  return out;
}

}  // namespace

LandmarkDataset load_landmark_dataset(const std::string& spec) {
  if (spec.rfind("mrclam:", 0) == 0) {
    const std::size_t colon = spec.rfind(':');
    const std::string dir = colon > 6 ? spec.substr(7, colon - 7) : "";
    const std::string robot_text = colon > 6 ? spec.substr(colon + 1) : "";
    char* end = nullptr;
    const long robot = std::strtol(robot_text.c_str(), &end, 10);
    if (dir.empty() || robot_text.empty() || *end != '\0' || robot < 1 || robot > 5)
      throw InputError("--dataset", 0, "dataset", "mrclam:DIR:ROBOT needs a folder and a robot 1..5, got \"" + spec + "\"");
    return read_mrclam_dataset(dir, int(robot));
  }
  if (spec.rfind("victoria:", 0) == 0) {
    const std::string dir = spec.substr(9);
    if (dir.empty()) throw InputError("--dataset", 0, "dataset", "victoria:DIR needs a folder");
    return read_victoria_park(dir);
  }
  throw InputError("--dataset", 0, "dataset", "expected mrclam:DIR:ROBOT or victoria:DIR, got \"" + spec + "\"");
}

Eigen::Vector3d dataset_truth_at(const LandmarkDataset& ds, double t) {
  const auto& T = ds.truth_times;
  if (T.empty()) throw InputError(ds.name, 0, "truth", "the dataset has no ground truth");
  auto it = std::lower_bound(T.begin(), T.end(), t);
  if (it == T.begin()) return ds.truth_poses.front();
  if (it == T.end()) return ds.truth_poses.back();
  const std::size_t k = static_cast<std::size_t>(it - T.begin());
  const double w = (t - T[k - 1]) / std::max(1e-9, T[k] - T[k - 1]);
  const Eigen::Vector3d a = ds.truth_poses[k - 1], b = ds.truth_poses[k];
  Eigen::Vector3d p = a + w * (b - a);
  p.z() = wrap_angle(a.z() + w * wrap_angle(b.z() - a.z()));
  return p;
}

Eigen::Vector2d dataset_measurement_sigmas(const LandmarkDataset& ds) {
  const RangeBearingModel h(1, 1);
  std::vector<double> ar, ab;
  for (const auto& e : ds.events) {
    if (!e.is_scan) continue;
    const Eigen::Vector3d x = dataset_truth_at(ds, e.time);
    for (const RangeBearing& z : e.observations)
      for (const auto& [id, m] : ds.true_landmarks)
        if (id == z.id) {
          const Eigen::Vector2d nu = RangeBearingModel::innovation(z, h.predict(x, m));
          ar.push_back(std::abs(nu.x())), ab.push_back(std::abs(nu.y()));
        }
  }
  if (ar.empty()) throw InputError(ds.name, 0, "observations", "no sighting of a surveyed landmark");
  // Robust σ = 1.4826 · median |residual| (the sightings have outliers).
  auto mad = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return 1.4826 * v[v.size() / 2];
  };
  return {mad(ar), mad(ab)};
}

double aligned_rms(const std::vector<Eigen::Vector2d>& est, const std::vector<Eigen::Vector2d>& ref) {
  if (est.empty() || est.size() != ref.size()) return std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix2d R;
  Eigen::Vector2d t;
  align_2d(est, ref, &R, &t);
  double s = 0;
  for (std::size_t k = 0; k < est.size(); ++k) s += (R * est[k] + t - ref[k]).squaredNorm();
  return std::sqrt(s / double(est.size()));
}

DatasetModels dataset_models(const LandmarkDataset& ds, const UnicycleNoise& n, double sensor_scale) {
  DatasetModels m;
  if (ds.motion_model == "victoria_park") {
    const double deg = kPi / 180;
    m.motion = std::make_shared<VictoriaParkModel>(VictoriaParkGeometry{}, 2.0, 6 * deg);
    m.sensor = RangeBearingModel(1.0 * sensor_scale, 3 * deg * sensor_scale);
    m.description = "victoria_park car model (sigma_v 2 m/s, sigma_steer 6 deg), sensor sigma 1 m, 3 deg";
    return m;
  }
  const Eigen::Vector2d sigma = sensor_scale * dataset_measurement_sigmas(ds);
  m.motion = std::make_shared<UnicycleModel>(n.sigma_v, n.sigma_w, n.sigma_v_per_v, n.sigma_w_per_w);
  m.sensor = RangeBearingModel(sigma.x(), sigma.y());
  m.description = "unicycle (sigma_v " + std::to_string(n.sigma_v) + " + " + std::to_string(n.sigma_v_per_v) +
                  "|v|, sigma_w " + std::to_string(n.sigma_w) + " + " + std::to_string(n.sigma_w_per_w) +
                  "|w|), sensor sigma " + std::to_string(sigma.x()) + " m, " + std::to_string(sigma.y()) +
                  " rad (robust, from the Vicon)";
  return m;
}

DatasetRunResult run_filter_on_dataset(LandmarkFilter* filter, const MotionModel& dead_reckoning,
                                       const LandmarkDataset& ds, const DatasetRunOptions& options) {
  DatasetRunResult r;
  r.dataset = ds.name;
  FilterRunResult& run = r.run;
  const bool truth = has_truth(ds);
  int total_scans = 0;
  for (const auto& e : ds.events) total_scans += e.is_scan;
  Eigen::Vector3d dr = ds.initial_pose;
  double t_total = 0, t_scans = 0, se_pos = 0, se_head = 0, se_dr = 0, nees_sum = 0;
  run.step_ms.reserve(ds.events.size());
  for (const auto& e : ds.events) {
    const double t0 = thread_cpu_ms();
    if (e.is_scan)
      filter->update(e.observations);
    else
      filter->predict(e.control);
    const double ms = thread_cpu_ms() - t0;
    t_total += ms;
    r.time_per_step_max_ms = std::max(r.time_per_step_max_ms, ms);
    run.step_ms.push_back(ms);
    ++r.events;
    if (!e.is_scan) {
      dr = dead_reckoning.predict(dr, e.control);
      continue;
    }
    t_scans += ms;
    ++r.scans;
    const Eigen::Vector3d x = filter->pose();
    const Eigen::Matrix3d P = filter->pose_covariance();
    const int map_size = int(filter->landmarks().size());
    if (!x.allFinite() || !P.allFinite()) run.finite = false;
    run.time.push_back(e.time);
    run.estimate.push_back(x);
    run.covariance.push_back(P);
    run.landmarks.push_back(map_size);
    r.dead_reckoning.push_back(dr);
    double nees = std::numeric_limits<double>::quiet_NaN();
    if (truth) {
      const Eigen::Vector3d xt = dataset_truth_at(ds, e.time);
      run.truth.push_back(xt);
      Eigen::Vector3d err = x - xt;
      err.z() = wrap_angle(err.z());
      se_pos += err.head<2>().squaredNorm();
      se_head += err.z() * err.z();
      se_dr += (xt.head<2>() - dr.head<2>()).squaredNorm();
      // A particle set collapsed onto one pose has a singular covariance: no NEES there.
      if (P.determinant() > 1e-30) {
        nees = err.dot(P.inverse() * err);
        nees_sum += nees, ++r.nees_scans;
      }
    }
    run.nees.push_back(nees);
    if (options.progress && options.progress_every > 0 && r.scans % options.progress_every == 0)
      options.progress(r.scans, total_scans, map_size, t_total / r.events);
  }
  if (r.events > 0) r.time_per_step_mean_ms = t_total / r.events;
  if (r.scans > 0) r.time_per_scan_ms = t_scans / r.scans;
  run.final_map = filter->landmarks();
  r.landmarks = int(run.final_map.size());
  for (const auto& lm : run.final_map)
    if (!lm.mean.allFinite() || !lm.covariance.allFinite()) run.finite = false;
  if (truth && r.scans > 0) {
    r.rmse_position = std::sqrt(se_pos / r.scans);
    r.rmse_heading = std::sqrt(se_head / r.scans);
    r.dead_reckoning_rmse_position = std::sqrt(se_dr / r.scans);
    if (r.nees_scans > 0) r.mean_nees = nees_sum / r.nees_scans;
  }
  double se_map = 0;
  for (const LandmarkEstimate& lm : run.final_map)
    for (const auto& [id, m] : ds.true_landmarks)
      if (id == lm.id) se_map += (lm.mean - m).squaredNorm(), ++r.mapped_true_landmarks;
  if (r.mapped_true_landmarks > 0) r.map_rmse = std::sqrt(se_map / r.mapped_true_landmarks);
  if (!ds.gps_times.empty()) {
    std::vector<Eigen::Vector2d> e_m, d_m, g_m;
    for (const auto& [j, k] : match_gps(run.time, ds))
      e_m.push_back(run.estimate[j].head<2>()), d_m.push_back(r.dead_reckoning[j].head<2>()),
          g_m.push_back(ds.gps_positions[k]);
    r.gps_matched = int(g_m.size());
    r.gps_rms = aligned_rms(e_m, g_m);
    r.dead_reckoning_gps_rms = aligned_rms(d_m, g_m);
  }
  return r;
}

SvgWriter plot_dataset_run(const std::string& label, const DatasetRunResult& r, const LandmarkDataset& ds) {
  const double w = 620, h = 520;
  const FilterRunResult& run = r.run;
  std::vector<Eigen::Vector2d> true_map;
  for (const auto& [id, m] : ds.true_landmarks) true_map.push_back(m);
  const bool truth = !run.truth.empty();
  SvgWriter svg(truth ? 2 * w : w, h);
  if (truth) {
    svg.embed(plot_filter_map(run, true_map, label + " on " + r.dataset + ": trajectory and map", w, h), 0, 0);
    svg.embed(plot_filter_errors(run, label + " on " + r.dataset + ": error against the Vicon and ±3σ", w, h), w, 0);
    return svg;
  }
  // No ground truth: estimate, dead reckoning and the GPS fixes mapped into the estimate's
  // frame (the inverse of the alignment of the estimate onto the GPS).
  Plot p(label + " on " + r.dataset + ": estimate, dead reckoning, GPS (aligned)", "x [m]", "y [m]");
  p.set_equal_aspect(true);
  Plot::Series est, dead, gps;
  est.label = "estimate", est.color = palette(0), est.width = 1.6;
  dead.label = "dead reckoning", dead.color = Rgb{150, 150, 150}, dead.width = 1.2, dead.dash = "5 3";
  gps.label = "GPS", gps.color = Rgb{40, 40, 40}, gps.points = true, gps.opacity = 0.6, gps.width = 0.0;
  for (std::size_t k = 0; k < run.estimate.size(); ++k) {
    est.x.push_back(run.estimate[k].x()), est.y.push_back(run.estimate[k].y());
    dead.x.push_back(r.dead_reckoning[k].x()), dead.y.push_back(r.dead_reckoning[k].y());
  }
  const auto matches = match_gps(run.time, ds);
  if (matches.size() >= 2) {
    std::vector<Eigen::Vector2d> e_m, g_m;
    for (const auto& [j, k] : matches) e_m.push_back(run.estimate[j].head<2>()), g_m.push_back(ds.gps_positions[k]);
    Eigen::Matrix2d R;
    Eigen::Vector2d t;
    align_2d(e_m, g_m, &R, &t);
    for (const auto& g : ds.gps_positions) {
      const Eigen::Vector2d q = R.transpose() * (g - t);
      gps.x.push_back(q.x()), gps.y.push_back(q.y());
    }
  }
  p.add_series(dead);
  p.add_series(est);
  if (!gps.x.empty()) p.add_series(gps);
  Plot::Series lm;
  lm.label = "landmarks", lm.color = palette(3), lm.points = true, lm.width = 0.0;
  for (const auto& m : run.final_map) lm.x.push_back(m.mean.x()), lm.y.push_back(m.mean.y());
  if (!lm.x.empty()) p.add_series(lm);
  svg.embed(p.render(w, h), 0, 0);
  return svg;
}

}  // namespace slamkit
