// Calibration acceptance (issue 16) on generated problems, written to
// bench/results/calibration.json:
//   * sim:calib2d and sim:calib3d, seeds 1..10: estimate − truth per parameter, |error|/σ,
//     chi2 with calibration on and off (calibration variables held at the nominal values);
//   * calib2d: the estimate from initial calibration guesses at truth·(1 ± 20%) (offset
//     translation ± 20% of max(|t|, 0.1 m), angle ± 20% of max(|θ|, 0.1 rad)) against the
//     estimate from the nominal guess;
//   * calib2d path=line: the warnings must name the baseline and the offset translation.
// Usage: calibration_bench [--out FILE]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "slamkit/core/calibration.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/sim/calibration_generator.h"

using namespace slamkit;

namespace {

PoseGraphResult run(PoseGraph g, bool calibrate) {
  PoseGraphOptimizerOptions o;
  if (!calibrate) o.problem.calibration.offsets = o.problem.calibration.odometry = false;
  return optimize_pose_graph(g, o);
}

double truth_of(const CalibrationTruth& t, const std::string& name) {
  for (const auto& [n, v] : t)
    if (n == name) return v;
  return NAN;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/calibration.json";
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--out" && i + 1 < argc) out = argv[++i];
    else {
      std::fprintf(stderr, "usage: calibration_bench [--out FILE]\n");
      return 2;
    }
  }
  nlohmann::json j;
  j["deg_per_rad"] = 180.0 / kPi;
  for (const std::string world : {"calib2d", "calib3d"}) {
    nlohmann::json rows = nlohmann::json::array();
    int within_tolerance = 0, within_3sigma = 0;
    double worst_t = 0, worst_r = 0, worst_wheel = 0, min_chi2_ratio = INFINITY;
    for (std::uint32_t seed = 1; seed <= 10; ++seed) {
      CalibrationSimOptions so;
      so.world = world;
      so.laps = world == "calib3d" ? 5 : 3;
      so.seed = seed;
      CalibrationTruth truth;
      const PoseGraph g = generate_calibration_problem(so, &truth);
      const PoseGraphResult on = run(g, true), off = run(g, false);
      nlohmann::json row = {{"seed", seed}, {"chi2_calibrated", on.final_chi2}, {"chi2_uncalibrated", off.final_chi2},
                            {"edges", g.edges.size()}, {"iterations", on.summary.iterations}};
      double et2 = 0, er = 0, ewheel = 0;
      bool all3 = true;
      nlohmann::json params = nlohmann::json::array();
      for (const CalibrationParameterEstimate& p : on.calibration.parameters) {
        const double t = truth_of(truth, p.name), err = p.value - t;
        const double z = std::abs(err) / p.sigma;
        all3 = all3 && z <= 3.0;
        params.push_back({{"name", p.name}, {"value", p.value}, {"sigma", p.sigma}, {"truth", t}, {"error", err}, {"z", z}});
        if (ends_with(p.name, ".x") || ends_with(p.name, ".y") || ends_with(p.name, ".z")) et2 += err * err;
        else if (ends_with(p.name, ".theta") || ends_with(p.name, ".rx") || ends_with(p.name, ".ry") || ends_with(p.name, ".rz"))
          er = std::max(er, std::abs(err));
        else ewheel = std::max(ewheel, std::abs(err / t));
      }
      const double et = std::sqrt(et2);
      const bool ok = et <= 0.01 && er <= 0.2 * kPi / 180 && ewheel <= 0.005;
      within_tolerance += ok;
      within_3sigma += all3;
      worst_t = std::max(worst_t, et), worst_r = std::max(worst_r, er), worst_wheel = std::max(worst_wheel, ewheel);
      min_chi2_ratio = std::min(min_chi2_ratio, off.final_chi2 / on.final_chi2);
      row["parameters"] = params;
      row["offset_translation_error_m"] = et;
      row["offset_rotation_error_deg"] = er * 180 / kPi;
      row["wheel_relative_error_max"] = ewheel;
      row["within_tolerance"] = ok;
      row["truth_within_3sigma"] = all3;
      rows.push_back(row);
      std::printf("%s seed %2u: offset %.4f m %.4f deg, wheel %.4f%%, all within 3 sigma %d, chi2 %.1f (off: %.1f)\n",
                  world.c_str(), seed, et, er * 180 / kPi, 100 * ewheel, all3, on.final_chi2, off.final_chi2);
      std::fflush(stdout);
    }
    j[world] = {{"seeds", rows},
                {"seeds_within_tolerance", within_tolerance},
                {"seeds_truth_within_3sigma", within_3sigma},
                {"worst_offset_translation_error_m", worst_t},
                {"worst_offset_rotation_error_deg", worst_r * 180 / kPi},
                {"worst_wheel_relative_error", worst_wheel},
                {"min_chi2_ratio_uncalibrated_over_calibrated", min_chi2_ratio}};
  }
  // Initial-guess independence (calib2d, seeds 1..3, 8 corners of ±20%).
  {
    nlohmann::json rows = nlohmann::json::array();
    double worst_z = 0;
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      CalibrationSimOptions so;
      so.seed = seed;
      CalibrationTruth truth;
      const PoseGraph base = generate_calibration_problem(so, &truth);
      PoseGraph ref_graph = base;
      const PoseGraphResult ref = run(ref_graph, true);
      for (int corner = 0; corner < 8; ++corner) {
        PoseGraph g = base;
        const double sign[3] = {corner & 1 ? 1.0 : -1.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 1.0 : -1.0};
        for (CalibrationVertex& v : g.calibration.vertices) {
          if (v.kind == CalibrationKind::kOffset2) {
            const double t[3] = {truth[0].second, truth[1].second, truth[2].second};
            v.value[0] = t[0] + 0.2 * sign[0] * std::max(std::abs(t[0]), 0.1);
            v.value[1] = t[1] + 0.2 * sign[1] * std::max(std::abs(t[1]), 0.1);
            v.value[2] = t[2] + 0.2 * sign[2] * std::max(std::abs(t[2]), 0.1);
          } else {
            for (int k = 0; k < 3; ++k) v.value[k] = truth[3 + k].second * (1.0 + 0.2 * sign[k]);
          }
        }
        const PoseGraphResult r = run(g, true);
        double z = 0;
        for (std::size_t k = 0; k < r.calibration.parameters.size(); ++k)
          z = std::max(z, std::abs(r.calibration.parameters[k].value - ref.calibration.parameters[k].value) /
                              ref.calibration.parameters[k].sigma);
        worst_z = std::max(worst_z, z);
        rows.push_back({{"seed", seed}, {"corner", corner}, {"max_difference_in_sigmas", z}, {"chi2", r.final_chi2},
                        {"chi2_nominal_start", ref.final_chi2}});
      }
      std::printf("initial guess ±20%%, seed %u: worst difference %.3g sigma\n", seed, worst_z);
    }
    j["initial_guess"] = {{"runs", rows}, {"worst_difference_in_sigmas", worst_z}};
  }
  // Unobservable: a straight line.
  {
    CalibrationSimOptions so;
    so.path = "line";
    PoseGraph g = generate_calibration_problem(so);
    const PoseGraphResult r = run(g, true);
    j["straight_line"] = {{"warnings", r.calibration.warnings}, {"held", r.calibration.held}};
    for (const std::string& w : r.calibration.warnings) std::printf("straight line: %s\n", w.c_str());
  }
  std::ofstream(out) << j.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
