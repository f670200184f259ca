// FastSLAM step cost against the map size (issue 15): generated worlds of n = 100, 1,000,
// 10,000 landmarks (sim/landmark_sim, the default density, so the number in view is the same
// for every n), M = 100 particles, FastSLAM 1.0 and 2.0 with known association. Every particle
// starts from the same map of all n landmarks (set_common_map: one shared tree), so each step
// works against a map of n landmarks: with the copy-on-write tree a step costs O(M log n)
// (lookups and path copies) and resampling O(M). For contrast the bench also times what a
// flat per-particle map would pay at each resampling: copying n landmarks for each of the M
// particles, O(M n). Writes bench/results/fastslam_scaling.json.
// Usage: fastslam_bench [--steps N] [--out FILE]
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_data.h"
#include "slamkit/eval/plot.h"
#include "slamkit/filters/fastslam.h"
#include "slamkit/sim/landmark_sim.h"

using namespace slamkit;


int main(int argc, char** argv) {
  int steps = 2000;
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/fastslam_scaling.json";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--steps")) steps = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
  }
  const int M = 100;
  nlohmann::json rows = nlohmann::json::array();
  for (int version : {1, 2}) {
    for (int n : {100, 1000, 10000}) {
      std::vector<Eigen::Vector2d> landmarks, waypoints;
      generate_landmark_world(n, 7, &landmarks, &waypoints);
      LandmarkSimOptions so;
      so.max_steps = steps;
      const LandmarkSimRun run = simulate_landmark_run(landmarks, waypoints, so, 1);
      FastSlamOptions o;
      o.version = version;
      o.particles = M;
      FastSlam f(std::make_shared<BicycleModel>(so.wheelbase, so.sigma_v, so.sigma_steer),
                 RangeBearingModel(so.sigma_range, so.sigma_bearing), o);
      PersistentLandmarkMap prior;
      for (int i = 0; i < n; ++i) {
        LandmarkGaussian g;
        g.mean = landmarks[static_cast<std::size_t>(i)];
        g.covariance = Eigen::Matrix2d::Identity() * 0.01;
        prior.set(i, g);
      }
      f.set_common_map(prior);
      double total = 0, scan_total = 0, scan_max = 0;
      int scans = 0, observations = 0;
      for (const LandmarkSimStep& s : run.steps) {
        const double t0 = bench::thread_cpu_ms();
        f.predict(Control{s.v, s.steer, so.dt});
        if (s.observed) f.update(s.observations);
        const double ms = bench::thread_cpu_ms() - t0;
        total += ms;
        if (s.observed) {
          ++scans;
          scan_total += ms;
          scan_max = std::max(scan_max, ms);
          observations += static_cast<int>(s.observations.size());
        }
      }
      std::vector<const PersistentLandmarkMap*> maps;
      for (const FastSlamParticle& p : f.particles()) maps.push_back(&p.map);
      const std::size_t nodes = PersistentLandmarkMap::distinct_nodes(maps);
      // What a flat map per particle would pay per resampling: M copies of n landmarks.
      std::vector<LandmarkGaussian> flat(static_cast<std::size_t>(n));
      const double c0 = bench::thread_cpu_ms();
      std::size_t sink = 0;
      for (int k = 0; k < M; ++k) {
        std::vector<LandmarkGaussian> copy = flat;
        sink += copy.size();
      }
      const double flat_ms = bench::thread_cpu_ms() - c0;
      const double per_step = total / static_cast<double>(run.steps.size());
      std::printf("fastslam%d n=%5d M=%d: %.4f ms/step, %.3f ms/scan (max %.3f), %.1f obs/scan, %d resamples, "
                  "%zu tree nodes for %d particles (flat maps: %d), flat copy per resampling %.3f ms (sink %zu)\n",
                  version, n, M, per_step, scan_total / scans, scan_max, observations / double(scans),
                  f.resample_count(), nodes, M, M * n, flat_ms, sink);
      rows.push_back({{"algorithm", version == 1 ? "fastslam1" : "fastslam2"}, {"landmarks", n}, {"particles", M},
                      {"control_steps", run.steps.size()}, {"scans", scans},
                      {"observations_per_scan", observations / double(scans)},
                      {"time_per_step_ms", per_step},
                      {"scan_ms_per_observation_per_log2n", scan_total / observations / std::log2(double(n))}, {"time_per_scan_ms", {{"mean", scan_total / scans}, {"max", scan_max}}},
                      {"resamples", f.resample_count()}, {"tree_nodes", nodes}, {"flat_map_entries", M * n},
                      {"flat_copy_per_resampling_ms", flat_ms}});
    }
  }
  nlohmann::json doc = {{"benchmark", "fastslam_scaling"},
                        {"description", "FastSLAM time per control step against the map size n (prior map of n landmarks "
                                        "shared by all particles), M = 100, known association, Release, 1 thread, thread CPU time"},
                        {"command", "build/bench/fastslam_bench --steps " + std::to_string(steps)},
                        {"results", rows}};
  std::ofstream(out) << doc.dump(2) << "\n";
  // Time per step against log10 n, with what O(n) from the n = 100 point would be.
  Plot plot("FastSLAM time per step (M = 100, known ids)", "log10 landmarks n", "ms per control step");
  plot.set_log_y(true);
  const Rgb colors[2] = {{31, 119, 180}, {214, 39, 40}};
  for (int v = 0; v < 2; ++v) {
    Plot::Series s;
    s.label = v == 0 ? "FastSLAM 1.0" : "FastSLAM 2.0";
    s.color = colors[v];
    s.points = true;
    for (const auto& r : rows)
      if (r["algorithm"] == (v == 0 ? "fastslam1" : "fastslam2"))
        s.x.push_back(std::log10(r["landmarks"].get<double>())), s.y.push_back(r["time_per_step_ms"].get<double>());
    Plot::Series linear;
    linear.label = v == 0 ? "O(n) from n = 100" : "";
    linear.color = Rgb{127, 127, 127};
    linear.dash = "5 4";
    for (std::size_t k = 0; k < s.x.size(); ++k) linear.x.push_back(s.x[k]), linear.y.push_back(s.y[0] * std::pow(10, s.x[k] - s.x[0]));
    plot.add_series(s);
    plot.add_series(linear);
  }
  const std::string svg = out.substr(0, out.rfind('.')) + ".svg";
  std::ofstream(svg) << plot.render(720, 480).str();
  std::printf("wrote %s\n", svg.c_str());
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
