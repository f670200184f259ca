// Phase-by-phase profile of the default pose-graph pipeline (load → gauge → ordering → init →
// problem → optimizer set-up / symbolic analysis / iterations → write-back), median over
// --repeat runs of each phase, per graph. Prints a Markdown table per graph and writes JSON.
// Also getrusage counters of each optimize_pose_graph call (minor page faults, system / user
// CPU ms, context switches): median, min and the first (cold, as in the CLI) run.
//   pose_graph_profile [--repeat 5] [--only SUBSTRING] [--threads N]
//                      [--out bench/results/pose_graph_profile.json] [--glibc-heap]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <sys/resource.h>

#include "bench_data.h"
#include "slamkit/core/process_heap.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/linear/blas_runtime.h"

using namespace slamkit;

namespace {

// CPU seconds of this process (all threads): unlike wall time, not inflated when other
// processes hold the cores.
double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Kernel-side costs of a region that user-space instruction counts miss: minor page faults
// (first touch of fresh pages: glibc mmaps blocks above its threshold and unmaps them on free,
// so a re-allocation faults again), system CPU time, context switches.
struct Rusage {
  double minflt = 0, stime_ms = 0, utime_ms = 0, nvcsw = 0, nivcsw = 0;
  static Rusage now() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    Rusage r;
    r.minflt = static_cast<double>(u.ru_minflt);
    r.stime_ms = 1e3 * static_cast<double>(u.ru_stime.tv_sec) + 1e-3 * static_cast<double>(u.ru_stime.tv_usec);
    r.utime_ms = 1e3 * static_cast<double>(u.ru_utime.tv_sec) + 1e-3 * static_cast<double>(u.ru_utime.tv_usec);
    r.nvcsw = static_cast<double>(u.ru_nvcsw);
    r.nivcsw = static_cast<double>(u.ru_nivcsw);
    return r;
  }
  Rusage operator-(const Rusage& o) const {
    return {minflt - o.minflt, stime_ms - o.stime_ms, utime_ms - o.utime_ms, nvcsw - o.nvcsw, nivcsw - o.nivcsw};
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Phases in pipeline order, in milliseconds, from one run.
std::vector<std::pair<std::string, double>> phases_ms(double load_s, const PoseGraphResult& r) {
  const PoseGraphPhaseTimes& p = r.phases;
  const Summary& s = r.summary;
  double eval = 0.0, assemble = 0.0, solve = 0.0;
  for (const IterationSummary& it : s.trace) eval += it.evaluate_time_s, assemble += it.assemble_time_s,
                                               solve += it.linear_solver_time_s;
  const double first_linearize = s.time_linearize_s - assemble;
  const double iterations = s.time_total_s - s.time_setup_s - s.time_analyze_s - first_linearize;
  return {{"load (apart)", 1e3 * load_s},
          {"input chi2", 1e3 * p.input_chi2_s},
          {"ordering", 1e3 * p.ordering_s},
          {"gauge / connectivity", 1e3 * p.gauge_s},
          {"init: spanning tree", 1e3 * r.init.time_tree_s},
          {"init: symbolic analyses", 1e3 * r.init.time_analyze_s},
          {"init: assemble", 1e3 * r.init.time_assemble_s},
          {"init: factorize + solve", 1e3 * r.init.time_solve_s},
          {"init: landmarks / rest", 1e3 * (p.init_s - r.init.time_tree_s - r.init.time_analyze_s -
                                            r.init.time_assemble_s - r.init.time_solve_s)},
          {"chi2 after init", 1e3 * p.chi2_after_init_s},
          {"problem build", 1e3 * p.problem_s},
          {"optimizer set-up (NormalEquations, threads)", 1e3 * s.time_setup_s},
          {"optimizer symbolic analysis", 1e3 * s.time_analyze_s},
          {"first linearization", 1e3 * first_linearize},
          {"iterations: factorize + solve", 1e3 * solve},
          {"iterations: evaluate candidate", 1e3 * eval},
          {"iterations: assemble H, g", 1e3 * assemble},
          {"iterations: rest (retract, checks)", 1e3 * (iterations - solve - eval - assemble)},
          {"write-back + final chi2", 1e3 * p.write_back_s},
          {"end-to-end (init + optimize)", 1e3 * r.time_total_s}};
}

}  // namespace

int main(int argc, char** argv) {
  reexec_with_better_blas_core(argv);  // same BLAS kernels as the CLI uses
  // The CLI's heap policy (slamkit/core/process_heap.h): freed memory stays in the heap, the first
  // 4 MiB sit on huge pages, so run 1 here faults the pages the CLI's run faults. --glibc-heap keeps glibc's.
  bool glibc_heap = false;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--glibc-heap") {
      glibc_heap = true;
      for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
      --argc;
      break;
    }
  if (!glibc_heap) configure_process_heap();
  std::string repeat_s = "5", threads_s = "0", only,
              out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/pose_graph_profile.json";
  if (!bench::parse_options(argc, argv, "[--repeat 5] [--only SUBSTRING] [--threads N] [--out FILE] [--glibc-heap]",
                            {{"--repeat", &repeat_s}, {"--only", &only}, {"--threads", &threads_s}, {"--out", &out}}))
    return 2;
  const int repeat = bench::int_option("--repeat", repeat_s, 1, 100000);
  const int threads = bench::int_option("--threads", threads_s, 0, 256);
  const auto root = bench::data_root() / "posegraph";
  if (!std::filesystem::exists(root)) {
    std::fprintf(stderr, "SKIPPED: dataset folder not found: %s (set SLAMKIT_DATA)\n", root.c_str());
    return 0;
  }
  nlohmann::json results = nlohmann::json::array();
  for (const bench::Reference& ref : bench::references()) {
    if (!only.empty() && std::string(ref.file).find(only) == std::string::npos) continue;
    const std::string path = (root / ref.file).string();
    std::map<std::string, std::vector<double>> samples;
    std::vector<std::string> names;
    PoseGraphResult last;
    std::map<std::string, double> first_run;  // the rusage counters of run 1
    for (int k = 0; k < repeat; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      PoseGraph g = read_pose_graph(path);
      const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      PoseGraphOptimizerOptions o;
      o.optimizer.num_threads = threads;
      const double cpu0 = process_cpu_s();
      const Rusage u0 = Rusage::now();
      last = optimize_pose_graph(g, o);
      const Rusage du = Rusage::now() - u0;
      const double cpu_s = process_cpu_s() - cpu0;
      names.clear();
      for (const auto& [name, ms] : phases_ms(load_s, last)) samples[name].push_back(ms), names.push_back(name);
      samples["process CPU time (all threads)"].push_back(1e3 * cpu_s);
      names.push_back("process CPU time (all threads)");
      // getrusage of the timed region (not ms): the first run of a file is the cold one the
      // CLI (and bench/side_by_side) measures; later ones reuse the heap.
      const std::pair<const char*, double> counters[] = {{"minor page faults (count)", du.minflt},
                                                         {"system CPU ms", du.stime_ms},
                                                         {"user CPU ms", du.utime_ms},
                                                         {"voluntary context switches", du.nvcsw},
                                                         {"involuntary context switches", du.nivcsw}};
      for (const auto& [name, v] : counters) {
        samples[name].push_back(v), names.push_back(name);
        if (k == 0) first_run[name] = v;
      }
    }
    std::printf("\n### %s: %d iterations, %d linear solves, init %s, chi2 %.6f, %d threads\n\n", std::string(ref.file).c_str(),
                last.summary.iterations, last.summary.linear_solves, to_string(last.init.used), last.final_chi2,
                last.summary.threads);
    std::printf("| phase | ms (median of %d) | ms (min) | run 1 |\n|---|---|---|---|\n", repeat);
    nlohmann::json phases = nlohmann::json::array(), phases_min = nlohmann::json::array();
    for (const std::string& n : names) {
      const double m = median(samples[n]);
      const double lo = *std::min_element(samples[n].begin(), samples[n].end());
      const auto f = first_run.find(n);
      if (f == first_run.end()) std::printf("| %s | %.2f | %.2f | |\n", n.c_str(), m, lo);
      else std::printf("| %s | %.2f | %.2f | %.2f |\n", n.c_str(), m, lo, f->second);
      phases.push_back({n, m});
      phases_min.push_back({n, lo});
    }
    results.push_back({{"file", ref.file},
                       {"iterations", last.summary.iterations},
                       {"linear_solves", last.summary.linear_solves},
                       {"init", to_string(last.init.used)},
                       {"init_analyses", last.init.analyses},
                       {"final_chi2", last.final_chi2},
                       {"threads", last.summary.threads},
                       {"linear_solver", last.summary.linear_solver},
                       {"blas", last.summary.blas},
                       {"phases_ms", phases},  // [name, median] in pipeline order
                       {"phases_min_ms", phases_min},
                       {"first_run_rusage", first_run}});
    std::fflush(stdout);
  }
  std::ofstream(out) << nlohmann::json({{"repeat", repeat}, {"results", results}}).dump(1) << "\n";
  std::printf("\nwrote %s\n", out.c_str());
  return 0;
}
