#pragma once
// The BLAS that CHOLMOD's supernodal kernels run on, as found at run time.
//
// Debian's OpenBLAS is built for many CPUs and picks its kernels when it is loaded. A release
// does not know CPU models newer than itself: OpenBLAS 0.3.21 (Debian 12) on an Emerald Rapids
// Xeon (family 6, model 207) falls back to its generic "Prescott" SSE3 kernels, which make a
// supernodal factorization about 2× slower (sphere2500: 79 ms instead of 41 ms). OpenBLAS reads
// OPENBLAS_CORETYPE only while it loads, so the fix is to set it and start the program again.
#include <string>

namespace slamkit {

struct BlasRuntime {
  std::string vendor;  ///< "OpenBLAS", or "unknown" when libblas.so.3 is another BLAS
  std::string core;    ///< the kernel set OpenBLAS chose ("SkylakeX", "Haswell", ...), "" if unknown
  std::string config;  ///< OpenBLAS's build configuration string
};

BlasRuntime blas_runtime();

/// The OpenBLAS kernel set this CPU can run when OpenBLAS chose a weaker generic one
/// (e.g. "SkylakeX" on an AVX-512 CPU it did not recognise); "" when nothing is to be gained.
std::string better_openblas_core();

/// OpenBLAS's thread count; no effect with another BLAS or when threads ≤ 0.
void set_blas_threads(int threads);

/// While alive (and active), OpenMP parallel regions started from the calling thread run with
/// one thread: max-active-levels 0, a per-task ICV since OpenMP 5, so other threads of the
/// program keep their setting. Restored on destruction. No effect without an OpenMP runtime.
class SerialOpenMpScope {
 public:
  explicit SerialOpenMpScope(bool active = true);
  ~SerialOpenMpScope();
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  int previous_ = -1;  ///< the level to restore, -1 when nothing was changed
};

/// For programs (the CLI, the benchmarks): when better_openblas_core() names a kernel set and
/// neither OPENBLAS_CORETYPE nor SLAMKIT_KEEP_BLAS_CORE is set, re-executes the running program
/// with OPENBLAS_CORETYPE set to it. Returns (without effect) when nothing is to be done or
/// the re-exec fails; never returns when it succeeds.
void reexec_with_better_blas_core(char** argv);

}  // namespace slamkit
