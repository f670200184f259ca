// Run-time view of OpenBLAS (see blas_runtime.h). Every OpenBLAS symbol is looked up with
// dlsym, so this compiles and runs against any BLAS.
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

}  // namespace

BlasRuntime blas_runtime() {
  BlasRuntime r;
  using GetString = char* (*)();
  auto corename = reinterpret_cast<GetString>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  auto config = reinterpret_cast<GetString>(dlsym(RTLD_DEFAULT, "openblas_get_config"));
  if (!corename) {
    r.vendor = "unknown";
    return r;
  }
  r.vendor = "OpenBLAS";
  if (const char* c = corename()) r.core = c;
  if (config)
    if (const char* c = config()) r.config = c;
  return r;
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
