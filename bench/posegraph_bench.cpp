// Dataset benchmark: every solver configuration on every reference pose graph, end-to-end
// (initialization + optimization; file loading reported apart), median of --repeat runs.
// Writes a JSON file and prints a table with the ratios to the reference figures.
//   posegraph_bench [--repeat 5] [--configs default|all] [--only SUBSTRING] [--threads N]
//                   [--out bench/results/posegraph.json]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bench_data.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/linear/blas_runtime.h"

using namespace slamkit;

namespace {

struct Config {
  std::string name;
  Algorithm algorithm;
  InitMethod init;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  reexec_with_better_blas_core(argv);  // same BLAS kernels as the CLI uses
  std::string repeat_s = "5", threads_s = "0", configs = "default", only,
              out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/posegraph.json";
  if (!bench::parse_options(argc, argv,
                            "[--repeat 5] [--configs default|all] [--only SUBSTRING] [--threads N] [--out FILE]",
                            {{"--repeat", &repeat_s}, {"--configs", &configs}, {"--only", &only},
                             {"--threads", &threads_s}, {"--out", &out}}))
    return 2;
  const int repeat = bench::int_option("--repeat", repeat_s, 1, 100000),
            threads = bench::int_option("--threads", threads_s, 0, 256);
  std::vector<Config> cfgs = {{"default (gn, auto init)", Algorithm::kGaussNewton, InitMethod::kAuto}};
  if (configs == "all") {
    for (Algorithm a : {Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM, Algorithm::kDogleg})
      cfgs.push_back({std::string(to_string(a)) + ", auto init", a, InitMethod::kAuto});
    cfgs.push_back({"gn, no init (file estimates)", Algorithm::kGaussNewton, InitMethod::kNone});
    cfgs.push_back({"lm, no init (file estimates)", Algorithm::kLevenbergMarquardt, InitMethod::kNone});
  }
  const auto root = bench::data_root() / "posegraph";
  if (!std::filesystem::exists(root)) {
    std::fprintf(stderr, "SKIPPED: dataset folder not found: %s (set SLAMKIT_DATA)\n", root.c_str());
    return 0;
  }
  nlohmann::json results = nlohmann::json::array();
  std::printf("%-34s %-28s %12s %9s %5s %9s %9s %8s %8s\n", "file", "config", "final chi2", "rel.gap", "iter",
              "e2e [s]", "peer [s]", "ratio", "load[s]");
  for (const bench::Reference& ref : bench::references()) {
    if (!only.empty() && ref.file.find(only) == std::string::npos) continue;
    const std::string path = (root / ref.file).string();
    const auto t0 = std::chrono::steady_clock::now();
    const PoseGraph original = read_pose_graph(path);
    const double load = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const Config& c : cfgs) {
      std::vector<double> e2e, init_t, opt_t, lin_t;
      PoseGraphResult last;
      for (int r = 0; r < repeat; ++r) {
        PoseGraph g = original;
        PoseGraphOptimizerOptions o;
        o.init = c.init;
        o.optimizer.algorithm = c.algorithm;
        o.optimizer.num_threads = threads;
        last = optimize_pose_graph(g, o);
        e2e.push_back(last.time_total_s);
        init_t.push_back(last.init.time_s);
        opt_t.push_back(last.summary.time_total_s);
        lin_t.push_back(last.summary.time_linear_solver_s / std::max(1, last.summary.linear_solves));
      }
      const double t = median(e2e);
      const double gap = (last.final_chi2 - ref.best_chi2) / ref.best_chi2;
      std::printf("%-34s %-28s %12.6f %9.1e %5d %9.4f %9.3f %8.3f %8.4f%s\n", ref.file.c_str(), c.name.c_str(),
                  last.final_chi2, gap, last.summary.iterations, t, ref.peer_seconds, t / ref.peer_seconds, load,
                  last.final_chi2 <= ref.accept_chi2 ? "" : "  (chi2 NOT reached)");
      std::fflush(stdout);
      results.push_back({{"file", ref.file},
                         {"config", c.name},
                         {"solver", to_string(c.algorithm)},
                         {"init", to_string(last.init.used)},
                         {"final_chi2", last.final_chi2},
                         {"best_chi2", ref.best_chi2},
                         {"chi2_reached", last.final_chi2 <= ref.accept_chi2},
                         {"relative_gap", gap},
                         {"iterations", last.summary.iterations},
                         {"linear_solves", last.summary.linear_solves},
                         {"time_end_to_end_s_median", t},
                         {"time_end_to_end_s_all", e2e},
                         {"time_init_s_median", median(init_t)},
                         {"time_optimize_s_median", median(opt_t)},
                         {"time_per_linear_solve_s_median", median(lin_t)},
                         {"time_load_s", load},
                         {"peer_seconds", ref.peer_seconds},
                         {"peer", ref.peer},
                         {"ratio_to_best_peer", t / ref.peer_seconds},
                         {"speed_goal_0_7", ref.speed_goal},
                         {"linear_solver", last.summary.linear_solver},
                         {"ordering", last.summary.ordering},
                         {"threads", last.summary.threads},
                         {"blas_threads", last.summary.blas_threads},
                         {"blas", last.summary.blas},
                         {"repeat", repeat}});
    }
  }
  std::ofstream f(out);
  f << results.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
