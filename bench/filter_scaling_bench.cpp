// Time per step against the number of landmarks (issue 15), two ways, thread CPU time:
//  - route: generated worlds of N = 100, 1,000, 10,000 landmarks along a closed route (same
//    density), one run each (seed 1), known association; every control step (predict, and the
//    update when a scan arrives) is timed and binned by the map size at that step. SEIF and
//    FastSLAM run the whole route; EKF runs until its budget is spent (its step costs O(n²)).
//  - survey: the first update is a survey scan of the whole world (sim/survey_scan), so the map
//    holds all N landmarks from the start and the next S route steps are timed at exactly N.
//    This is how the EKF is timed at 10,000 landmarks (a 20,003² covariance, 3.2 GB) without
//    the 200,000-step route that would take days at O(n²) per scan.
// Writes bench/results/filters_scaling.json (route) / filters_scaling_survey.json and their SVGs;
// the survey mode also draws filters_time_per_step.svg, every family on one log-log plot.
// --mode plot only redraws that combined plot from the JSON files in --out.
//   filter_scaling_bench [--mode route|survey|plot] [--active A] [--ekf-budget SECONDS] [--steps S]
//                        [--sizes 100,1000,10000] [--algorithms ekf,seif,...] [--out DIR]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <tuple>

#include "bench_data.h"
#include "slamkit/core/string_list.h"
#include "slamkit/eval/filter_plots.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/sim/landmark_sim.h"

using namespace slamkit;

namespace {

struct Config {
  std::string mode = "route";
  int active = 6;
  double ekf_budget = 120;
  int survey_steps = 400;
  std::vector<int> sizes = {100, 1000, 10000};
  std::vector<std::string> algorithms = {"seif", "seif-entropy", "ekf"};
};

LandmarkFilterOptions filter_options(const LandmarkSimOptions& sim, const Config& c, int landmarks) {
  LandmarkFilterOptions fo;
  fo.motion = std::make_shared<BicycleModel>(sim.wheelbase, sim.sigma_v, sim.sigma_steer);
  fo.sensor = RangeBearingModel(sim.sigma_range, sim.sigma_bearing);
  fo.active_landmarks = c.active;
  fo.expected_landmarks = landmarks;
  return fo;
}

std::string label(const std::string& algorithm, const Config& c) {
  return algorithm + (algorithm.rfind("seif", 0) == 0 ? " A=" + std::to_string(c.active) : "");
}

// One route run binned by map size (4 bins per decade).
nlohmann::json route_run(const std::string& algorithm, int n, const Config& c, std::vector<TimingSeries>* plot) {
  const LandmarkSimOptions sim;
  std::vector<Eigen::Vector2d> lm, wp;
  generate_landmark_world(n, 1, &lm, &wp);
  const LandmarkSimRun run = simulate_landmark_run(lm, wp, sim, 1);
  auto f = make_landmark_filter(algorithm, filter_options(sim, c, 0));
  std::map<int, std::pair<double, long>> bins;  // bin → (Σ ms, steps)
  double total = 0, final_sum = 0, max_ms = 0;
  long final_steps = 0, steps = 0;
  int map_size = 0;
  bool complete = true;
  const std::size_t final_from = run.steps.size() * 9 / 10;
  for (std::size_t k = 0; k < run.steps.size(); ++k) {
    const auto& s = run.steps[k];
    const double t0 = bench::thread_cpu_ms();
    f->predict(Control{s.v, s.steer, sim.dt});
    if (s.observed) f->update(s.observations);
    const double ms = bench::thread_cpu_ms() - t0;
    if (s.observed) map_size += f->last_update().new_landmarks;
    total += ms, max_ms = std::max(max_ms, ms), ++steps;
    if (map_size > 0) {
      auto& b = bins[int(std::floor(std::log10(map_size) * 4))];
      b.first += ms, b.second += 1;
    }
    if (k >= final_from) final_sum += ms, ++final_steps;
    if (algorithm == "ekf" && total > 1000 * c.ekf_budget) {
      complete = false;
      break;
    }
  }
  TimingSeries ts;
  ts.label = label(algorithm, c) + ", route generated:" + std::to_string(n);
  nlohmann::json curve = nlohmann::json::array();
  for (const auto& [bin, v] : bins) {
    const double size = std::pow(10.0, (bin + 0.5) / 4);
    ts.landmarks.push_back(size);
    ts.ms.push_back(v.first / v.second);
    curve.push_back({{"landmarks", size}, {"ms", v.first / v.second}, {"steps", v.second}});
  }
  plot->push_back(ts);
  std::fprintf(stderr, "%-13s generated:%-6d %s %ld/%zu steps, map %d, %.4f ms/step mean, last 10%%: %.4f\n",
               algorithm.c_str(), n, complete ? "complete" : "budget ", steps, run.steps.size(), map_size,
               total / steps, final_steps ? final_sum / final_steps : NAN);
  return {{"algorithm", algorithm}, {"world", "generated:" + std::to_string(n)}, {"route_steps", run.steps.size()},
          {"steps_run", steps}, {"complete", complete}, {"final_landmarks", map_size},
          {"time_per_step_ms_mean", total / steps}, {"time_per_step_ms_max", max_ms},
          {"time_per_step_ms_last_10pct", complete && final_steps ? nlohmann::json(final_sum / final_steps) : nlohmann::json()},
          {"total_s", total / 1000}, {"by_map_size", curve}};
}

// Survey first, then the first S route steps at exactly n landmarks.
nlohmann::json survey_run(const std::string& algorithm, int n, const Config& c) {
  LandmarkSimOptions sim;
  sim.max_steps = c.survey_steps;
  std::vector<Eigen::Vector2d> lm, wp;
  generate_landmark_world(n, 1, &lm, &wp);
  const LandmarkSimRun run = simulate_landmark_run(lm, wp, sim, 1);
  auto f = make_landmark_filter(algorithm, filter_options(sim, c, n));
  double t0 = bench::thread_cpu_ms();
  f->update(survey_scan(lm, Eigen::Vector3d::Zero(), sim, 1000 + n));
  const double survey_ms = bench::thread_cpu_ms() - t0;
  const int map_size = f->last_update().new_landmarks;
  double total = 0, max_ms = 0, scan_total = 0;
  long scans = 0, observations = 0;
  for (const auto& s : run.steps) {
    t0 = bench::thread_cpu_ms();
    f->predict(Control{s.v, s.steer, sim.dt});
    if (s.observed) f->update(s.observations);
    const double ms = bench::thread_cpu_ms() - t0;
    total += ms, max_ms = std::max(max_ms, ms);
    if (s.observed) scan_total += ms, ++scans, observations += long(s.observations.size());
  }
  const long steps = long(run.steps.size());
  std::fprintf(stderr, "%-13s survey generated:%-6d map %d (survey update %.0f ms), %ld steps: %.4f ms/step mean, %.3f max, %.3f ms/scan (%.1f observations)\n",
               algorithm.c_str(), n, map_size, survey_ms, steps, total / steps, max_ms, scan_total / scans,
               double(observations) / scans);
  return {{"algorithm", algorithm}, {"world", "generated:" + std::to_string(n)}, {"landmarks", map_size},
          {"survey_update_ms", survey_ms}, {"steps", steps}, {"scans", scans},
          {"observations_per_scan", double(observations) / scans},
          {"time_per_step_ms", {{"mean", total / steps}, {"max", max_ms}}}, {"time_per_scan_ms", scan_total / scans}};
}

// One series per label from the rows of `key` in a results file (absent file: nothing);
// row(r) gives (label, landmarks, ms per step).
template <class Row>
void series_by_algorithm(const std::string& file, const char* key, std::vector<TimingSeries>* out, const Row& row) {
  std::ifstream in(file);
  if (!in) return;
  const nlohmann::json doc = nlohmann::json::parse(in);
  std::map<std::string, TimingSeries> by_label;
  for (const auto& r : doc[key]) {
    const auto [label, landmarks, ms] = row(r);
    TimingSeries& ts = by_label[label];
    ts.label = label, ts.landmarks.push_back(landmarks), ts.ms.push_back(ms);
  }
  for (auto& [label, ts] : by_label) out->push_back(ts);
}

// The one plot of time per step against n: the survey series, plus (when their JSON is
// in `dir`) the route curves of the largest generated world (SEIF's flat line) and FastSLAM's
// prior-map scaling (fastslam_bench), and an n² reference through the EKF's first point.
std::vector<TimingSeries> combined_series(const std::string& dir) {
  std::vector<TimingSeries> out;
  series_by_algorithm(dir + "/filters_scaling_survey.json", "runs", &out, [](const nlohmann::json& r) {
    return std::make_tuple(r["algorithm"].get<std::string>() + ", survey", r["landmarks"].get<double>(),
                           r["time_per_step_ms"]["mean"].get<double>());
  });
  const std::vector<TimingSeries> survey = out;
  for (const TimingSeries& s : survey)
    if (s.label.rfind("ekf", 0) == 0 && !s.ms.empty()) {
      TimingSeries ref{"n² through EKF at " + std::to_string(int(s.landmarks[0])), {}, {}};
      for (double n : s.landmarks) ref.landmarks.push_back(n), ref.ms.push_back(s.ms[0] * std::pow(n / s.landmarks[0], 2));
      out.push_back(ref);
    }
  std::ifstream route(dir + "/filters_scaling.json");
  if (route) {
    const nlohmann::json doc = nlohmann::json::parse(route);
    std::map<std::string, const nlohmann::json*> largest;  // algorithm → its run on the largest world
    for (const auto& r : doc["runs"]) {
      const auto*& best = largest[r["algorithm"].get<std::string>()];
      if (!best || r["route_steps"].get<long>() > (*best)["route_steps"].get<long>()) best = &r;
    }
    for (const auto& [algorithm, r] : largest) {
      TimingSeries ts{algorithm + " A=" + std::to_string(doc["active"].get<int>()) + ", route " +
                          (*r)["world"].get<std::string>(), {}, {}};
      for (const auto& b : (*r)["by_map_size"]) ts.landmarks.push_back(b["landmarks"]), ts.ms.push_back(b["ms"]);
      out.push_back(ts);
    }
  }
  series_by_algorithm(dir + "/fastslam_scaling.json", "results", &out, [](const nlohmann::json& r) {
    return std::make_tuple(r["algorithm"].get<std::string>() + " M=" + std::to_string(r["particles"].get<int>()) +
                               ", prior map",
                           r["landmarks"].get<double>(), r["time_per_step_ms"].get<double>());
  });
  return out;
}

void draw_combined(const std::string& dir) {
  std::ofstream(dir + "/filters_time_per_step.svg")
      << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << plot_time_per_step(combined_series(dir), "time per step against landmarks in the map", 1000, 620).str();
  std::fprintf(stderr, "wrote %s/filters_time_per_step.svg\n", dir.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  Config c;
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--mode") c.mode = v;
    else if (a == "--active") c.active = bench::int_option(a, v, 1, 1 << 20);
    else if (a == "--ekf-budget") c.ekf_budget = bench::double_option(a, v, 0.0, 1e6);
    else if (a == "--steps") c.survey_steps = bench::int_option(a, v, 1, 1 << 24);
    else if (a == "--out") out = v;
    else if (a == "--sizes" || a == "--algorithms") {
      if (a == "--sizes") c.sizes.clear(); else c.algorithms.clear();
      for (const std::string& w : split_list(v))
        if (a == "--sizes") c.sizes.push_back(bench::int_option(a, w, 1, 1 << 24)); else c.algorithms.push_back(w);
    } else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (c.mode == "plot") return draw_combined(out), 0;
  if (c.mode != "route" && c.mode != "survey") return std::fprintf(stderr, "--mode route|survey|plot\n"), 2;
  nlohmann::json doc;
  doc["active"] = c.active;
  std::vector<TimingSeries> plot;
  if (c.mode == "route") {
    doc["what"] = "time per control step (predict + update) vs landmarks in the map; generated worlds, seed 1, known association, thread CPU time";
    doc["ekf_budget_s"] = c.ekf_budget;
    for (const std::string& algorithm : c.algorithms)
      for (int n : c.sizes) doc["runs"].push_back(route_run(algorithm, n, c, &plot));
  } else {
    doc["what"] = "time per control step at exactly N landmarks: a survey scan of the whole world first, then the first "
                  "route steps; generated worlds, seed 1, known association, thread CPU time";
    doc["steps"] = c.survey_steps;
    for (const std::string& algorithm : c.algorithms) {
      TimingSeries ts;
      ts.label = label(algorithm, c) + ", survey";
      for (int n : c.sizes) {
        nlohmann::json r = survey_run(algorithm, n, c);
        ts.landmarks.push_back(r["landmarks"]);
        ts.ms.push_back(r["time_per_step_ms"]["mean"]);
        doc["runs"].push_back(r);
      }
      // Growth exponent between consecutive sizes: time ∝ n^p (EKF: p → 2; SEIF: p ≈ 0).
      for (std::size_t i = 1; i < ts.ms.size(); ++i)
        doc["growth_exponent"][algorithm].push_back(std::log(ts.ms[i] / ts.ms[i - 1]) /
                                                    std::log(ts.landmarks[i] / ts.landmarks[i - 1]));
      plot.push_back(ts);
    }
  }
  const std::string stem = out + (c.mode == "route" ? "/filters_scaling" : "/filters_scaling_survey");

  std::ofstream(stem + ".json") << doc.dump(2) << "\n";
  std::ofstream(stem + ".svg") << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                               << plot_time_per_step(plot, c.mode == "route" ? "time per step vs landmarks in the map (route)"
                                                                             : "time per step at N landmarks (survey first)",
                                                     1000, 620).str();
  std::fprintf(stderr, "wrote %s.json / .svg\n", stem.c_str());
  if (c.mode == "survey") draw_combined(out);
  return 0;
}
