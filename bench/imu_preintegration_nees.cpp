// Preintegration consistency on real IMU data (issue 12): integrate the TUM-VI room1–4 and
// EuRoC V1_01/V1_02/V2_03 IMU streams between ground-truth states over 0.5 s and 1 s windows
// and report the NEES of the 9-dof error [r_R, r_v, r_p] per window and its mean, written to
// bench/results/imu_preintegration_nees.json. See vio/imu_consistency.h for the model:
//   nees_imu_only   rᵀ P_imu⁻¹ r        (datasheet noise densities only)
//   nees            rᵀ (P_imu + P_gt)⁻¹ r (plus the ground truth's own errors)
// Biases: a constant-bias least-squares fit per sequence and window length, with the
// gravity direction of the mocap frame (fit-v:fit-bias+tilt, velocities from the fit);
// EuRoC also with its ground-truth velocity and bias columns (gt-v:gt-bias).
// mean_nees_vinsmono_noise: the same windows under VINS-Mono's inflated noise values.
// Usage: imu_preintegration_nees [--out FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_data.h"
#include "slamkit/io/imu_io.h"
#include "slamkit/io/trajectory_io.h"
#include "slamkit/vio/imu_consistency.h"

using namespace slamkit;

namespace {

struct Sequence {
  std::string name, gt, imu;
  bool euroc;
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
double sig4(double x) {  // 4 significant digits keep the JSON small
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", x);
  return std::stod(b);
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

// NEES of the sub-block [o, o + 3) (rotation 0, velocity 3, position 6).
double block_nees(const ImuWindowError& e, int o) {
  const Eigen::Matrix3d P = (e.P_imu + e.P_gt).block<3, 3>(o, o);
  const Eigen::Vector3d r = e.residual.segment<3>(o);
  return r.dot(P.ldlt().solve(r));
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/imu_preintegration_nees.json";
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--out" && i + 1 < argc) out = argv[++i];
    else {
      std::fprintf(stderr, "usage: imu_preintegration_nees [--out FILE]\n");
      return 2;
    }
  }
  const auto root = bench::data_root() / "vio";
  std::vector<Sequence> seqs;
  for (int r = 1; r <= 4; ++r)
    seqs.push_back({"tumvi/room" + std::to_string(r), "tumvi/gt/dataset-room" + std::to_string(r) + "_512_16.csv",
                    "tumvi/imu/dataset-room" + std::to_string(r) + "_512_imu0.csv", false});
  seqs.push_back({"euroc/V1_01", "euroc/gt/V1_01_easy_gt_20hz.csv", "euroc/imu/V101_imu0.csv", true});
  seqs.push_back({"euroc/V1_02", "euroc/gt/V1_02_medium_gt.csv", "euroc/imu/V102_imu0.csv", true});
  seqs.push_back({"euroc/V2_03", "euroc/gt/V2_03_difficult_gt.csv", "euroc/imu/V203_imu0.csv", true});

  nlohmann::json j;
  j["state_dim"] = 9;
  j["block_dim"] = 3;  // mean_nees_rotation / _velocity / _position each expect 3
  j["model"] = "vio/imu_consistency.h: midpoint preintegration, datasheet noise densities (README), "
               "ground-truth errors (velocity fit, pose noise from local quadratic fits) mapped through the factor";
  nlohmann::json rows = nlohmann::json::array();
  for (const Sequence& s : seqs) {
    const std::vector<ImuMeasurement> imu = read_imu_csv((root / s.imu).string());
    Trajectory gt = read_trajectory((root / s.gt).string(), TrajectoryFormat::kEuroc);
    const Trajectory gt_orig = gt;
    const double rate = (gt.size() - 1) / (gt[gt.size() - 1].stamp - gt[0].stamp);
    const double half_width = rate > 50 ? 0.05 : 0.15;
    const GroundTruthDifferentiation d = differentiate_ground_truth(gt, half_width);
    Trajectory gt_v = gt;  // EuRoC also has velocities in its ground truth: a second variant
    if (s.euroc)
      for (std::size_t k = 0; k < gt.size(); ++k)
        if (gt_v[k].v_world) gt_v[k].v_world = gt_orig[k].v_world;
    std::vector<Eigen::Vector3d> gt_sigma(gt.size());
    for (std::size_t k = 0; k < gt.size(); ++k)
      gt_sigma[k] = Eigen::Vector3d(d.rotation_sigma, d.velocity_sigma[k], d.position_sigma);
    const ImuNoise noise = s.euroc ? ImuNoise::euroc() : ImuNoise::tumvi();
    const Eigen::Vector3d g(0, 0, s.euroc ? -9.81007 : -9.80766);
    for (double length : {0.5, 1.0}) {
      const std::vector<ImuWindow> windows = select_imu_windows(gt, imu, length, 0.1);
      Eigen::Vector3d g_fit;
      const ImuBias fitted_tilt = fit_constant_bias(imu, gt, windows, noise, g, gt_sigma, 3, &g_fit);
      for (const std::string& variant : s.euroc ? std::vector<std::string>{"gt-v:gt-bias", "fit-v:fit-bias+tilt"}
                                               : std::vector<std::string>{"fit-v:fit-bias+tilt"}) {
        const bool gt_velocity = variant.rfind("gt-v", 0) == 0;
        const std::string bias_source = variant.substr(variant.find(':') + 1) == "gt-bias" ? "gt" : "fit";
        const Eigen::Vector3d g_used_vec = bias_source == "gt" ? g : g_fit;
        const Trajectory& g_used = gt_velocity ? gt_v : gt;
        std::vector<double> nees, nees_imu, nr, nv, np;
        nlohmann::json per = nlohmann::json::array();
        for (const ImuWindow& w : windows) {
          const ImuBias b = bias_source == "gt" ? *gt_orig[w.i].bias : fitted_tilt;
          const ImuWindowError e = imu_window_error(imu, g_used[w.i], g_used[w.j], b, noise, g_used_vec, gt_sigma[w.i], gt_sigma[w.j]);
          nees.push_back(e.nees()), nees_imu.push_back(e.nees_imu_only());
          nr.push_back(block_nees(e, 0)), nv.push_back(block_nees(e, 3)), np.push_back(block_nees(e, 6));
          per.push_back({std::round(w.t0 * 1000) / 1000, std::round((w.t1 - w.t0) * 1000) / 1000, sig4(e.nees()),
                         sig4(e.nees_imu_only())});
        }
        // Mean NEES under VINS-Mono's (inflated) noise values for the same sensor.
        const auto mean_with = [&](const ImuNoise& nz) {
          double m = 0.0;
          for (const ImuWindow& w : windows) {
            const ImuBias b = bias_source == "gt" ? *gt_orig[w.i].bias : fitted_tilt;
            m += imu_window_error(imu, g_used[w.i], g_used[w.j], b, nz, g_used_vec, gt_sigma[w.i], gt_sigma[w.j]).nees();
          }
          return m / windows.size();
        };
        const ImuNoise vins = s.euroc ? ImuNoise{0.004, 0.08, 2e-6, 4e-5} : ImuNoise{0.004, 0.04, 2e-5, 4e-4};
        const double nees_vins = mean_with(vins);
        nlohmann::json row;
        row["mean_nees_vinsmono_noise"] = nees_vins;
        row["gravity_fitted"] = {g_fit.x(), g_fit.y(), g_fit.z()};
        row["sequence"] = s.name;
        row["window_s"] = length;
        row["bias"] = bias_source;
        row["velocity"] = gt_velocity ? "gt" : "fit";
        row["windows"] = windows.size();
        row["fitted_bias"] = {{"gyro", {fitted_tilt.gyro.x(), fitted_tilt.gyro.y(), fitted_tilt.gyro.z()}},
                              {"accel", {fitted_tilt.accel.x(), fitted_tilt.accel.y(), fitted_tilt.accel.z()}}};
        row["gt_position_sigma_m"] = d.position_sigma;
        row["gt_rotation_sigma_rad"] = d.rotation_sigma;
        row["gt_velocity_sigma_median_mps"] = median([&] {
          std::vector<double> v;
          for (const ImuWindow& w : windows) v.push_back(d.velocity_sigma[w.i]);
          return v;
        }());
        row["mean_nees"] = mean(nees);
        row["median_nees"] = median(nees);
        row["mean_nees_imu_only"] = mean(nees_imu);
        row["median_nees_imu_only"] = median(nees_imu);
        row["mean_nees_rotation"] = mean(nr);
        row["mean_nees_velocity"] = mean(nv);
        row["mean_nees_position"] = mean(np);
        row["within_factor_2"] = mean(nees) >= 4.5 && mean(nees) <= 18.0;
        row["per_window"] = per;  // [t0 s, length s, nees, nees_imu_only]
        std::printf("%-12s T=%.1fs %-15s windows=%4zu  mean NEES %8.2f (median %6.2f; rot %6.2f vel %6.2f pos %6.2f)"
                    "  IMU-only %9.1f  VINS-noise %6.2f\n",
                    s.name.c_str(), length, variant.c_str(), windows.size(), mean(nees), median(nees), mean(nr),
                    mean(nv), mean(np), mean(nees_imu), nees_vins);
        std::fflush(stdout);
        rows.push_back(row);
      }
    }
  }
  j["runs"] = rows;
  std::ofstream(out) << j.dump(1) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
