// Shared by the benchmarks: dataset location and the reference figures from the issues
// (best known chi2, fastest peer end-to-end time, one bare CHOLMOD factorize+solve).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace slamkit::bench {

/// Thread CPU time in ms: on a shared machine wall time would measure the other jobs.
inline double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

inline std::filesystem::path data_root() {
  const char* env = std::getenv("SLAMKIT_DATA");
  std::filesystem::path p = env && *env ? env : "../shared/datasets";
  if (p.is_relative()) p = std::filesystem::path(SLAMKIT_SOURCE_DIR) / p;
  return p.lexically_normal();
}

struct Reference {
  std::string file;          ///< under posegraph/
  double best_chi2;          ///< best known chi2 (g2o definition)
  double accept_chi2;        ///< the acceptance bound (best · (1 + 1e-4), or the issue's bound)
  double peer_seconds;       ///< fastest peer end-to-end (g2o, Ceres 2.1, GTSAM 4.3), 0 if none given
  std::string peer;          ///< who and how
  double cholmod_ms;         ///< the issue's one-factorize+solve figure, 0 if none given
  bool speed_goal;           ///< in the issue's speed-goal list (≤ 0.7 × peer)
};

inline const std::vector<Reference>& references() {
  static const std::vector<Reference> r = {
      {"2d/input_INTEL_g2o.g2o", 215.83, 215.83 * (1 + 1e-4), 0.026, "g2o GN", 0, false},
      {"2d/intel.g2o", 45.0047, 45.0047 * (1 + 1e-4), 0.034, "Ceres", 0, false},
      {"2d/input_MITb_g2o.g2o", 41.1633, 41.1633 * (1 + 1e-4), 0.012, "g2o linear init + GN", 0, false},
      {"2d/input_M3500_g2o.g2o", 137.913, 137.913 * (1 + 1e-4), 0.116, "g2o linear init + GN", 9, true},
      {"2d/input_M3500b_g2o.g2o", 4468.09, 4511.08, 0.16, "g2o linear init (reaches 4511.08)", 0, false},
      {"2d/city10000.g2o", 511.985, 511.985 * (1 + 1e-4), 0.61, "GTSAM LAGO + LM", 44, true},
      {"2d/derived/manhattan_odominit.g2o", 3549.04, 3549.04 * (1 + 1e-4), 0.155, "g2o linear init + GN", 0, false},
      {"2d/derived/CSAIL_P_toro.g2o", 40.5551, 40.5551 * (1 + 1e-4), 0.018, "g2o", 0, false},
      {"3d/sphere2500.g2o", 727.149, 727.149 * (1 + 1e-4), 0.47, "GTSAM chordal + GN", 53, true},
      {"3d/torus3D.g2o", 14574.7, 14574.7 * (1 + 1e-4), 1.36, "GTSAM chordal + GN", 117, true},
      {"3d/parking-garage.g2o", 1.23868, 1.23868 * (1 + 1e-4), 0.16, "GTSAM GN", 15, true},
      {"3d/derived/cubicle_psd.g2o", 2379.91, 2379.91 * (1 + 1e-4), 1.56, "GTSAM chordal + GN", 131, true},
  };
  return r;
}

/// Parses "--name value" pairs into the given options (each holds its default). Prints the
/// usage and returns false on --help, an unknown option or a missing value: a tool that was
/// asked for help must not run (and overwrite committed results).
inline bool parse_options(int argc, char** argv, const char* usage, const std::map<std::string, std::string*>& opts) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto it = opts.find(a);
    if (a == "--help" || a == "-h" || it == opts.end() || i + 1 >= argc) {
      if (a != "--help" && a != "-h")
        std::fprintf(stderr, it == opts.end() ? "unknown option %s\n" : "option %s needs a value\n", a.c_str());
      std::fprintf(stderr, "usage: %s %s\n", argv[0], usage);
      return false;
    }
    *it->second = argv[++i];
  }
  return true;
}

/// An option's value as an integer in [lo, hi], or a message naming the option and exit 2 (a
/// bench must not abort with an uncaught std::stoi exception, nor run with a value it cannot use).
inline int int_option(const std::string& name, const std::string& v, int lo, int hi) {
  char* end = nullptr;
  const long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || x < lo || x > hi) {
    std::fprintf(stderr, "option %s: \"%s\" is not an integer in [%d, %d]\n", name.c_str(), v.c_str(), lo, hi);
    std::exit(2);
  }
  return static_cast<int>(x);
}

/// An option's value as a finite number in [lo, hi], or a message naming the option and exit 2.
inline double double_option(const std::string& name, const std::string& v, double lo, double hi) {
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end != '\0' || !(x >= lo && x <= hi)) {
    std::fprintf(stderr, "option %s: \"%s\" is not a number in [%g, %g]\n", name.c_str(), v.c_str(), lo, hi);
    std::exit(2);
  }
  return x;
}

}  // namespace slamkit::bench
