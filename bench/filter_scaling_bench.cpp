// Time per step against the number of landmarks: generated worlds of N = 100, 1,000, 10,000
// landmarks along a closed route (same density), one run each (seed 1), known association.
// Every control step (predict, and the update when a scan arrives) is timed; the times are
// binned by the map size at that step. SEIF runs the whole route at a fixed active bound;
// EKF runs until its time budget is spent (its per-step cost grows with n², and at 10,000
// landmarks its covariance alone would take 3.2 GB). Writes bench/results/filters_scaling.json
// and filters_scaling.svg.
//   filter_scaling_bench [--active A] [--ekf-budget SECONDS] [--sizes 100,1000,10000] [--out DIR]
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slamkit/eval/filter_plots.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/sim/landmark_sim.h"

using namespace slamkit;

// Thread CPU time: the machine is shared, wall time would measure the other jobs.
static double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

int main(int argc, char** argv) {
  int active = 6;
  double ekf_budget = 120;
  std::vector<int> sizes = {100, 1000, 10000};
  std::vector<std::string> algorithms = {"seif", "seif-entropy", "ekf"};
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--active")) active = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--ekf-budget")) ekf_budget = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
    else if (!std::strcmp(argv[i], "--sizes") || !std::strcmp(argv[i], "--algorithms")) {
      std::stringstream ss(argv[i + 1]);
      if (argv[i][2] == 's') sizes.clear(); else algorithms.clear();
      for (std::string w; std::getline(ss, w, ',');)
        if (argv[i][2] == 's') sizes.push_back(std::stoi(w)); else algorithms.push_back(w);
    }
  }
  LandmarkSimOptions sim;
  LandmarkFilterOptions fo;
  fo.motion = std::make_shared<BicycleModel>(sim.wheelbase, sim.sigma_v, sim.sigma_steer);
  fo.sensor = RangeBearingModel(sim.sigma_range, sim.sigma_bearing);
  fo.active_landmarks = active;
  nlohmann::json doc;
  doc["what"] = "time per control step (predict + update) vs landmarks in the map; generated worlds, seed 1, known association";
  doc["active"] = active;
  doc["ekf_budget_s"] = ekf_budget;
  std::vector<TimingSeries> plot;
  for (const std::string& algorithm : algorithms) {
    for (int n : sizes) {
      std::vector<Eigen::Vector2d> lm, wp;
      generate_landmark_world(n, 1, &lm, &wp);
      const LandmarkSimRun run = simulate_landmark_run(lm, wp, sim, 1);
      auto f = make_landmark_filter(algorithm, fo);
      std::map<int, std::pair<double, long>> bins;  // bin → (Σ ms, steps)
      double total = 0, final_sum = 0;
      long final_steps = 0, steps = 0;
      int map_size = 0;
      bool complete = true;
      const std::size_t final_from = run.steps.size() * 9 / 10;
      for (std::size_t k = 0; k < run.steps.size(); ++k) {
        const auto& s = run.steps[k];
        const double t0 = cpu_ms();
        f->predict(Control{s.v, s.steer, sim.dt});
        if (s.observed) f->update(s.observations);
        const double ms = cpu_ms() - t0;
        if (s.observed) map_size += f->last_update().new_landmarks;
        total += ms;
        ++steps;
        if (map_size > 0) {
          const int bin = int(std::floor(std::log10(map_size) * 4));  // 4 bins per decade
          bins[bin].first += ms;
          bins[bin].second += 1;
        }
        if (k >= final_from) final_sum += ms, ++final_steps;
        if (algorithm == "ekf" && total > 1000 * ekf_budget) {
          complete = false;
          break;
        }
      }
      TimingSeries ts;
      ts.label = algorithm + (algorithm == "ekf" ? "" : " A=" + std::to_string(active)) + ", generated:" + std::to_string(n);
      nlohmann::json curve = nlohmann::json::array();
      for (const auto& [bin, v] : bins) {
        const double size = std::pow(10.0, (bin + 0.5) / 4);
        ts.landmarks.push_back(size);
        ts.ms.push_back(v.first / v.second);
        curve.push_back({{"landmarks", size}, {"ms", v.first / v.second}, {"steps", v.second}});
      }
      plot.push_back(ts);
      nlohmann::json r = {{"algorithm", algorithm},
                          {"world", "generated:" + std::to_string(n)},
                          {"route_steps", run.steps.size()},
                          {"steps_run", steps},
                          {"complete", complete},
                          {"final_landmarks", map_size},
                          {"time_per_step_ms_mean", total / steps},
                          {"time_per_step_ms_last_10pct", complete && final_steps ? nlohmann::json(final_sum / final_steps) : nlohmann::json()},
                          {"total_s", total / 1000},
                          {"by_map_size", curve}};
      std::fprintf(stderr, "%-13s generated:%-6d %s %ld/%zu steps, map %d, %.4f ms/step mean, last 10%%: %.4f\n",
                   algorithm.c_str(), n, complete ? "complete" : "budget ", steps, run.steps.size(), map_size,
                   total / steps, final_steps ? final_sum / final_steps : NAN);
      doc["runs"].push_back(r);
    }
  }
  std::ofstream(out + "/filters_scaling.json") << doc.dump(2) << "\n";
  std::ofstream(out + "/filters_scaling.svg") << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                                              << plot_time_per_step(plot, "time per step vs landmarks in the map", 1000, 620).str();
  return 0;
}
