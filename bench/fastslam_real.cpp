// Every landmark-SLAM filter on the real datasets (issue 15, step 4), through the same replay
// loop as `slamkit filter --dataset` (eval/filter_dataset.h):
//   MRCLAM Dataset 7, robots 1–3, known association (barcodes), every filter of the family
//     against the Vicon ground truth: position and heading RMSE over the scans, mean pose
//     NEES, final map error, time per step. The sensor noise is estimated from the data
//     (README: "Estimate them yourself"), the unicycle noise is chosen, not fitted.
//   Victoria Park, nearest-neighbour association: time per step, landmarks in the map, and a
//     qualitative GPS check (RMS after a 2-D rigid alignment, next to dead reckoning).
// Writes bench/results/filters_real.json. Usage: fastslam_real [--particles M]
//   [--algorithms a,b,...] [--victoria-algorithms a,b,...] [--unicycle-noise sv,sw,sv_per_v,sw_per_w]
//   [--sensor-scale S] [--known-gate P (Gaussian filters: chi2_2 gate on known-id sightings)] [--skip-victoria 1] [--out FILE]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_data.h"
#include "slamkit/core/string_list.h"
#include "slamkit/eval/filter_dataset.h"
#include "slamkit/filters/filter_factory.h"

using namespace slamkit;

namespace {

nlohmann::json nullable(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json run_one(const std::string& algorithm, const LandmarkDataset& ds, const DatasetModels& models,
                       AssociationMethod association, int particles, int active, double known_gate) {
  LandmarkFilterOptions fo;
  fo.motion = models.motion;
  fo.sensor = models.sensor;
  fo.initial_pose = ds.initial_pose;
  fo.association.method = association;
  fo.association.known_gate_probability = known_gate;
  fo.particles = particles;
  fo.active_landmarks = active;
  auto filter = make_landmark_filter(algorithm, fo);
  DatasetRunOptions ro;
  ro.progress = [&](int done, int total, int lm, double ms) {
    std::printf("  %s %s: scan %d/%d, %d landmarks, %.4f ms/step so far\n", ds.name.c_str(), algorithm.c_str(), done,
                total, lm, ms);
    std::fflush(stdout);
  };
  const DatasetRunResult r = run_filter_on_dataset(filter.get(), *models.motion, ds, ro);
  std::printf("%s %-12s RMSE position %.3f m heading %.4f rad (dead reckoning %.3f m), mean NEES %.1f, map RMSE %.3f m, "
              "%d landmarks, GPS %.2f m (dead reckoning %.2f m), %.4f ms/step (max %.2f)%s\n",
              ds.name.c_str(), algorithm.c_str(), r.rmse_position, r.rmse_heading, r.dead_reckoning_rmse_position,
              r.mean_nees, r.map_rmse, r.landmarks, r.gps_rms, r.dead_reckoning_gps_rms, r.time_per_step_mean_ms,
              r.time_per_step_max_ms, r.run.finite ? "" : "  NON-FINITE");
  std::fflush(stdout);
  return {{"dataset", ds.name}, {"algorithm", algorithm},
          {"association", association == AssociationMethod::kKnown ? "known" : "nn"},
          {"particles", particles}, {"active", active}, {"known_gate_probability", known_gate}, {"events", r.events}, {"scans", r.scans},
          {"models", models.description},
          {"rmse_position", nullable(r.rmse_position)}, {"rmse_heading", nullable(r.rmse_heading)},
          {"dead_reckoning_rmse_position", nullable(r.dead_reckoning_rmse_position)},
          {"mean_pose_nees", nullable(r.mean_nees)}, {"scans_with_regular_covariance", r.nees_scans},
          {"map_rmse", nullable(r.map_rmse)}, {"landmarks", r.landmarks},
          {"gps_rms_after_alignment", nullable(r.gps_rms)},
          {"dead_reckoning_gps_rms_after_alignment", nullable(r.dead_reckoning_gps_rms)},
          {"gps_fixes_matched", r.gps_matched}, {"finite", r.run.finite},
          {"time_per_step_ms", {{"mean", r.time_per_step_mean_ms}, {"max", r.time_per_step_max_ms}}},
          {"time_per_scan_ms", r.time_per_scan_ms}};
}

}  // namespace

int main(int argc, char** argv) {
  int particles = 100, active = 6;
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/filters_real.json";
  std::vector<std::string> algorithms = landmark_filter_names(), victoria_algorithms = {"fastslam2"};
  UnicycleNoise noise;
  double sensor_scale = 1.0, known_gate = 0;
  bool skip_victoria = false;
  std::string command = "SLAMKIT_DATA=../shared/datasets build/bench/fastslam_real";
  for (int i = 1; i + 1 < argc; i += 2) {
    command += std::string(" ") + argv[i] + " " + argv[i + 1];
    if (!std::strcmp(argv[i], "--particles")) particles = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--active")) active = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
    if (!std::strcmp(argv[i], "--algorithms")) algorithms = split_list(argv[i + 1]);
    if (!std::strcmp(argv[i], "--victoria-algorithms")) victoria_algorithms = split_list(argv[i + 1]);
    if (!std::strcmp(argv[i], "--unicycle-noise") &&
        std::sscanf(argv[i + 1], "%lf,%lf,%lf,%lf", &noise.sigma_v, &noise.sigma_w, &noise.sigma_v_per_v,
                    &noise.sigma_w_per_w) != 4)
      return std::fprintf(stderr, "--unicycle-noise needs sv,sw,sv_per_v,sw_per_w\n"), 2;
    if (!std::strcmp(argv[i], "--known-gate")) known_gate = std::atof(argv[i + 1]);
    if (!std::strcmp(argv[i], "--sensor-scale")) sensor_scale = std::atof(argv[i + 1]);
    if (!std::strcmp(argv[i], "--skip-victoria")) skip_victoria = std::atoi(argv[i + 1]) != 0;
  }
  const auto root = bench::data_root() / "landmark";
  nlohmann::json mrclam = nlohmann::json::array(), victoria = nlohmann::json::array();
  for (int robot = 1; robot <= 3; ++robot) {
    const LandmarkDataset ds = read_mrclam_dataset((root / "MRCLAM_Dataset7").string(), robot);
    const DatasetModels models = dataset_models(ds, noise, sensor_scale);
    std::printf("%s: %zu events, %s\n", ds.name.c_str(), ds.events.size(), models.description.c_str());
    for (const std::string& a : algorithms)
      mrclam.push_back(run_one(a, ds, models, AssociationMethod::kKnown, particles, active, known_gate));
  }
  if (!skip_victoria) {
    const LandmarkDataset vp = read_victoria_park((root / "VictoriaPark").string());
    const DatasetModels models = dataset_models(vp);
    for (const std::string& a : victoria_algorithms)
      victoria.push_back(run_one(a, vp, models, AssociationMethod::kNearestNeighbour, particles, active, 0));
  }
  nlohmann::json doc = {{"benchmark", "filters_real"}, {"command", command},
                        {"timing", "thread CPU time, Release, 1 thread"},
                        {"unicycle_noise", {{"sigma_v", noise.sigma_v}, {"sigma_w", noise.sigma_w},
                                            {"sigma_v_per_v", noise.sigma_v_per_v}, {"sigma_w_per_w", noise.sigma_w_per_w}}},
                        {"sensor_sigma_scale", sensor_scale},
                        {"mrclam", mrclam}, {"victoria_park", victoria}};
  std::ofstream(out) << doc.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
