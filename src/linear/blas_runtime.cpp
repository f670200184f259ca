// Run-time view and control of OpenBLAS and OpenMP (see blas_runtime.h). Their symbols are
// looked up once with dlsym, so this compiles and runs against any BLAS, with or without OpenMP.
#include "slamkit/linear/blas_runtime.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace slamkit {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Kernel sets older than AVX2: what OpenBLAS falls back to on a CPU model it does not know.
bool is_generic_core(const std::string& core) {
  static const char* const kGeneric[] = {"prescott", "core2", "penryn", "dunnington", "nehalem", "atom",
                                         "katmai",   "coppermine", "northwood", "banias", "sandybridge"};
  const std::string c = lower(core);
  return std::any_of(std::begin(kGeneric), std::end(kGeneric), [&](const char* g) { return c == g; });
}

template <class F>
F lookup(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_DEFAULT, name));
}

struct Symbols {
  char* (*openblas_get_corename)() = lookup<char* (*)()>("openblas_get_corename");
  char* (*openblas_get_config)() = lookup<char* (*)()>("openblas_get_config");
  void (*openblas_set_num_threads)(int) = lookup<void (*)(int)>("openblas_set_num_threads");
  int (*omp_get_max_active_levels)() = lookup<int (*)()>("omp_get_max_active_levels");
  void (*omp_set_max_active_levels)(int) = lookup<void (*)(int)>("omp_set_max_active_levels");
};

const Symbols& symbols() {
  static const Symbols s;
  return s;
}

}  // namespace

BlasRuntime blas_runtime() {
  BlasRuntime r;
  const Symbols& s = symbols();
  if (!s.openblas_get_corename) {
    r.vendor = "unknown";
    return r;
  }
  r.vendor = "OpenBLAS";
  if (const char* c = s.openblas_get_corename()) r.core = c;
  if (s.openblas_get_config)
    if (const char* c = s.openblas_get_config()) r.config = c;
  return r;
}

void set_blas_threads(int threads) {
  if (threads > 0 && symbols().openblas_set_num_threads) symbols().openblas_set_num_threads(threads);
}

SerialOpenMpScope::SerialOpenMpScope(bool active) {
  const Symbols& s = symbols();
  if (!active || !s.omp_get_max_active_levels || !s.omp_set_max_active_levels) return;
  previous_ = s.omp_get_max_active_levels();
  s.omp_set_max_active_levels(0);
}

SerialOpenMpScope::~SerialOpenMpScope() {
  if (previous_ >= 0) symbols().omp_set_max_active_levels(previous_);
}

std::string better_openblas_core() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  const BlasRuntime r = blas_runtime();
  if (r.vendor != "OpenBLAS" || !is_generic_core(r.core)) return "";
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
    return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
#endif
  return "";
}

void reexec_with_better_blas_core(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") || std::getenv("SLAMKIT_KEEP_BLAS_CORE")) return;
  const std::string core = better_openblas_core();
  if (core.empty()) return;
  // Set even if the exec fails, so that no child process tries again.
  if (setenv("OPENBLAS_CORETYPE", core.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
}

}  // namespace slamkit
