// Odometry calibration on real data (issue 16): UTIAS MRCLAM Dataset 7, robots 1–3, whose
// odometry is the *commanded* (v, ω) of a unicycle. One graph holds all three robots: per robot
// a chain of keyframes every 2 s, an EDGE_SE2 from the Vicon ground truth between consecutive
// keyframes, and an EDGE_SE2_ODOM_DIFFERENTIAL_CALIB from the commanded velocities mapped to
// wheel velocities with a nominal baseline b₀ = 0.25 m (v_l,r = v ∓ ω b₀/2, time-averaged over
// the keyframe interval), with one VERTEX_ODOM_DIFFERENTIAL per robot. The estimated
// (k_l, k_r, b) give the scale factors of the commands:
//   s_v = (k_l + k_r)/2,   s_ω = (k_l + k_r) b₀ / (2b),   plus a coupling (k_r − k_l)/b (rad/m),
// with sigmas from the joint marginal covariance. Two passes: the second sets every edge
// group's information from the first pass's RMS residuals (per robot and component), so the
// sigmas carry the real scatter of the commands. A closed-form cross-check per robot:
// s_v = Σ|Δp_vicon| / Σ|v̄ dt| and s_ω = Σ Δθ_vicon ω̄ dt / Σ (ω̄ dt)².
// Dead reckoning over 30 s windows (nominal vs calibrated, in and out of sample) shows what
// the calibration buys; bench/results/mrclam_calibration_robotN.svg draws 120 s of it.
// Writes bench/results/mrclam_calibration.json and the graph as g2o (--graph FILE), which
// `slamkit optimize FILE` reads with the same tags.
// Usage: mrclam_calibration [--graph FILE] [--out FILE]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_data.h"
#include "slamkit/core/pose_graph_calibration.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/eval/plot.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/io/mrclam_odometry.h"

using namespace slamkit;

namespace {

double kKeyframe = 2.0;  // seconds (--keyframe); shorter keyframes bias the ω scale low (see docs)
double g_lag = 0.0;      // seconds the motion follows the command by (--lag)
constexpr double kB0 = 0.25;       // nominal baseline, metres

struct Built {
  PoseGraph g;
  std::vector<std::pair<std::size_t, std::size_t>> edge_ranges;  // per robot: its edges
  std::vector<std::vector<SE2>> vicon;                            // per robot: keyframe poses
  nlohmann::json robots = nlohmann::json::array();
};

// The one graph of all three robots over the fraction [from, to) of each robot's time span.
Built build(const std::vector<MrclamRobotLog>& data, double from, double to) {
  OdometryCalibrationGraphOptions o;
  o.keyframe_s = kKeyframe;
  o.nominal_baseline = kB0;
  o.from = from, o.to = to, o.lag_s = g_lag;
  OdometryCalibrationGraph og = build_odometry_calibration_graph(data, o);
  Built b;
  b.g = std::move(og.graph);
  b.edge_ranges = og.edge_ranges;
  b.vicon = og.vicon;
  for (std::size_t r = 0; r < data.size(); ++r) {
    const int n = static_cast<int>(b.vicon[r].size()) - 1;
    b.robots.push_back({{"robot", data[r].robot}, {"keyframes", n + 1}, {"duration_s", n * kKeyframe},
                        {"closed_form_v_scale", og.closed_form[r].v_scale},
                        {"closed_form_omega_scale", og.closed_form[r].omega_scale}});
  }
  return b;
}

// Two passes (the second with information from the first's RMS residuals), then per robot the
// parameters, sigmas and derived scale factors into b.robots.
PoseGraphResult estimate(Built& b) {
  PoseGraphOptimizerOptions o;
  o.init = InitMethod::kNone;  // the keyframes start at the Vicon poses
  PoseGraphResult r;
  for (int pass = 1; pass <= 2; ++pass) {
    PoseGraph run = b.g;
    r = optimize_pose_graph(run, o);
    std::printf("  pass %d: chi2 %.6g, %d iterations\n", pass, r.final_chi2, r.summary.iterations);
    if (pass == 2) {
      b.g = run;
      break;
    }
    for (const auto& [first, last] : b.edge_ranges) {
      for (int group = 0; group < 2; ++group) {
        Eigen::Vector3d sq = Eigen::Vector3d::Zero();
        int count = 0;
        for (std::size_t i = first; i < last; ++i) {
          if (static_cast<bool>(b.g.edges[i].calibrated) != (group == 0)) continue;
          sq += edge_error(run, run.edges[i]).cwiseAbs2();
          ++count;
        }
        const Eigen::Vector3d info = (sq / count).cwiseMax(1e-12).cwiseInverse();
        for (std::size_t i = first; i < last; ++i)
          if (static_cast<bool>(b.g.edges[i].calibrated) == (group == 0)) b.g.edges[i].information = info.asDiagonal();
      }
    }
  }
  for (int robot = 1; robot <= 3; ++robot) {
    nlohmann::json& jr = b.robots[static_cast<std::size_t>(robot - 1)];
    const std::string prefix = "odometry[" + std::to_string(1000000 + robot) + "].";
    int index = -1;
    for (std::size_t i = 0; i < r.calibration.parameters.size(); ++i)
      if (r.calibration.parameters[i].name == prefix + "k_left") index = static_cast<int>(i);
    if (index < 0) throw std::runtime_error("robot " + std::to_string(robot) + ": no odometry estimate");
    const auto& P = r.calibration.parameters;
    const double kl = P[index].value, kr = P[index + 1].value, bl = P[index + 2].value;
    const Eigen::Matrix3d C = r.calibration.covariance.block<3, 3>(index, index);
    const Eigen::RowVector3d Jv(0.5, 0.5, 0.0), Jw(kB0 / (2 * bl), kB0 / (2 * bl), -(kl + kr) * kB0 / (2 * bl * bl)),
        Jc(-1 / bl, 1 / bl, -(kr - kl) / (bl * bl));
    const char* names[] = {"k_left", "k_right", "baseline"};
    for (int k = 0; k < 3; ++k) jr[names[k]] = {{"value", P[index + k].value}, {"sigma", P[index + k].sigma}};
    jr["v_scale"] = {{"value", (kl + kr) / 2}, {"sigma", std::sqrt((Jv * C * Jv.transpose())(0))}};
    jr["omega_scale"] = {{"value", (kl + kr) * kB0 / (2 * bl)}, {"sigma", std::sqrt((Jw * C * Jw.transpose())(0))}};
    jr["v_to_omega_coupling_rad_per_m"] = {{"value", (kr - kl) / bl}, {"sigma", std::sqrt((Jc * C * Jc.transpose())(0))}};
    std::printf("  robot %d: k_l %.4f ± %.4f, k_r %.4f ± %.4f, b %.4f ± %.4f m -> v scale %.4f ± %.4f, omega scale "
                "%.4f ± %.4f (closed form %.4f, %.4f)\n",
                robot, kl, P[index].sigma, kr, P[index + 1].sigma, bl, P[index + 2].sigma, (kl + kr) / 2,
                jr["v_scale"]["sigma"].get<double>(), (kl + kr) * kB0 / (2 * bl), jr["omega_scale"]["sigma"].get<double>(),
                jr["closed_form_v_scale"].get<double>(), jr["closed_form_omega_scale"].get<double>());
  }
  return r;
}

Eigen::Vector3d estimated_k(const PoseGraph& g, int robot) {
  return Eigen::Vector3d(g.calibration.find(1000000 + robot)->value);
}

// Dead reckoning of robot r's odometry edges k0..k0+steps from the Vicon pose at k0, with K.
std::vector<SE2> dead_reckon(const Built& b, int robot, const Eigen::Vector3d& K, int k0, int steps) {
  const std::size_t first = b.edge_ranges[static_cast<std::size_t>(robot - 1)].first;
  std::vector<SE2> x{b.vicon[static_cast<std::size_t>(robot - 1)][static_cast<std::size_t>(k0)]};
  for (int k = k0; k < k0 + steps; ++k) {
    const Eigen::Vector3d& raw = b.g.edges[first + static_cast<std::size_t>(k)].calibrated->odometry;
    x.push_back(x.back() * to_se2(differential_drive_motion(K, raw[0], raw[1], raw[2])));
  }
  return x;
}

// Mean endpoint error of 30 s dead-reckoning windows starting in [from, to) of the keyframes.
double window_error(const Built& b, int robot, const Eigen::Vector3d& K, double from, double to) {
  const int kSteps = static_cast<int>(std::lround(30.0 / kKeyframe));
  const auto& v = b.vicon[static_cast<std::size_t>(robot - 1)];
  const int n = static_cast<int>(v.size()) - 1;
  double sum = 0;
  int count = 0;
  for (int k0 = static_cast<int>(from * n); k0 + kSteps <= static_cast<int>(to * n); k0 += kSteps) {
    sum += (dead_reckon(b, robot, K, k0, kSteps).back().translation() - v[static_cast<std::size_t>(k0 + kSteps)].translation()).norm();
    ++count;
  }
  return sum / count;
}

void trajectory_svg(const Built& b, int robot, const Eigen::Vector3d& K, const std::string& path) {
  const int kSteps = static_cast<int>(std::lround(120.0 / kKeyframe));
  Plot plot("MRCLAM 7, robot " + std::to_string(robot) + ": 120 s of dead reckoning from the commanded (v, omega)",
            "x [m]", "y [m]");
  plot.set_equal_aspect(true);
  auto series = [&](const std::vector<SE2>& x, const std::string& label, std::size_t colour) {
    Plot::Series s;
    s.label = label;
    s.color = palette(colour);
    for (const SE2& p : x) s.x.push_back(p.x()), s.y.push_back(p.y());
    plot.add_series(s);
  };
  const auto& v = b.vicon[static_cast<std::size_t>(robot - 1)];
  series(std::vector<SE2>(v.begin(), v.begin() + kSteps + 1), "Vicon", 0);
  series(dead_reckon(b, robot, Eigen::Vector3d(1, 1, kB0), 0, kSteps), "commands as given", 1);
  series(dead_reckon(b, robot, K, 0, kSteps), "commands through the estimated calibration", 2);
  std::ofstream(path) << plot.render(720, 560).str();
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/mrclam_calibration.json";
  std::string graph_path = "/tmp/mrclam7_calibration.g2o";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--graph" && i + 1 < argc) graph_path = argv[++i];
    else if (a == "--keyframe" && i + 1 < argc) kKeyframe = bench::double_option(a, argv[++i], 0.0, 1e6);
    else if (a == "--lag" && i + 1 < argc) g_lag = bench::double_option(a, argv[++i], 0.0, 1e6);
    else {
      std::fprintf(stderr, "usage: mrclam_calibration [--graph FILE] [--out FILE] [--keyframe S] [--lag S]\n");
      return 2;
    }
  }
  const std::filesystem::path dir = bench::data_root() / "landmark" / "MRCLAM_Dataset7";
  std::vector<MrclamRobotLog> data;
  for (int robot = 1; robot <= 3; ++robot) data.push_back(read_mrclam_robot(dir.string(), robot));
  nlohmann::json j;
  j["dataset"] = dir.string();
  j["keyframe_s"] = kKeyframe;
  j["command_lag_s"] = g_lag;
  j["nominal_baseline_m"] = kB0;
  std::printf("whole run (900 s per robot), one graph of three robots:\n");
  Built whole = build(data, 0.0, 1.0);
  const PoseGraphResult r = estimate(whole);
  j["robots"] = whole.robots;
  j["final_chi2"] = r.final_chi2;
  j["edges"] = whole.g.edges.size();
  j["poses"] = whole.g.vertices().size();
  j["calibration_warnings"] = r.calibration.warnings;
  write_pose_graph(whole.g, graph_path);
  j["graph"] = graph_path;
  // Three disjoint thirds: the spread of the estimates is an empirical check of the sigmas.
  nlohmann::json thirds = nlohmann::json::array();
  for (int k = 0; k < 3; ++k) {
    std::printf("third %d of the run:\n", k + 1);
    Built part = build(data, k / 3.0, (k + 1) / 3.0);
    estimate(part);
    thirds.push_back(part.robots);
  }
  j["thirds"] = thirds;
  // Dead reckoning over 30 s windows: nominal vs calibrated, in sample (whole-run calibration)
  // and out of sample (calibrated on the first third, evaluated on the other two).
  Built first_third = build(data, 0.0, 1.0 / 3.0);
  estimate(first_third);
  for (int robot = 1; robot <= 3; ++robot) {
    const Eigen::Vector3d nominal(1, 1, kB0), K = estimated_k(whole.g, robot), K1 = estimated_k(first_third.g, robot);
    nlohmann::json dr = {{"window_s", 30.0},
                         {"nominal_m", window_error(whole, robot, nominal, 0.0, 1.0)},
                         {"calibrated_in_sample_m", window_error(whole, robot, K, 0.0, 1.0)},
                         {"nominal_last_two_thirds_m", window_error(whole, robot, nominal, 1.0 / 3.0, 1.0)},
                         {"calibrated_on_first_third_m", window_error(whole, robot, K1, 1.0 / 3.0, 1.0)}};
    j["robots"][robot - 1]["dead_reckoning_30s_endpoint_error"] = dr;
    std::printf("robot %d: 30 s dead-reckoning endpoint error %.3f m nominal, %.3f m calibrated (in sample); last two "
                "thirds %.3f m nominal, %.3f m with the first third's calibration\n",
                robot, dr["nominal_m"].get<double>(), dr["calibrated_in_sample_m"].get<double>(),
                dr["nominal_last_two_thirds_m"].get<double>(), dr["calibrated_on_first_third_m"].get<double>());
    trajectory_svg(whole, robot, K,
                   std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/mrclam_calibration_robot" + std::to_string(robot) + ".svg");
  }
  // Spread of the thirds (sample std): the scale factors drift over the run far more than the
  // Hessian sigmas (white residuals) allow; std/√3 is an empirical sigma of the whole-run value.
  for (int robot = 0; robot < 3; ++robot) {
    for (const char* key : {"v_scale", "omega_scale"}) {
      double m = 0, q = 0;
      for (int k = 0; k < 3; ++k) m += thirds[k][robot][key]["value"].get<double>() / 3;
      for (int k = 0; k < 3; ++k) q += std::pow(thirds[k][robot][key]["value"].get<double>() - m, 2) / 2;
      j["robots"][robot][key]["thirds_std"] = std::sqrt(q);
      j["robots"][robot][key]["empirical_sigma"] = std::sqrt(q / 3);
      std::printf("robot %d %s: whole %.4f ± %.4f (Hessian), thirds std %.4f -> empirical sigma %.4f\n", robot + 1, key,
                  j["robots"][robot][key]["value"].get<double>(), j["robots"][robot][key]["sigma"].get<double>(),
                  std::sqrt(q), std::sqrt(q / 3));
    }
  }
  std::ofstream(out) << j.dump(2) << "\n";
  std::printf("wrote %s and %s\n", out.c_str(), graph_path.c_str());
  return 0;
}
