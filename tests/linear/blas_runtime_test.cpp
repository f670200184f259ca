// Run with OPENBLAS_CORETYPE=Prescott (see CMakeLists.txt): OpenBLAS then runs its generic SSE3
// kernels, as it does on CPUs it does not know, and better_openblas_core() must name the kernel
// set this CPU supports.
#include "slamkit/linear/blas_runtime.h"
#include "slamkit/linear/sparse_cholesky.h"

#include <gtest/gtest.h>

#include <dlfcn.h>

#include <cstdlib>
#include <string>

namespace slamkit {
namespace {

// The BLAS comes with CHOLMOD: a program that never uses the sparse Cholesky does not load it.
const bool kLinksCholesky = make_sparse_cholesky() != nullptr;

TEST(BlasRuntime, ReportsTheKernelsOpenBlasRuns) {
  ASSERT_TRUE(kLinksCholesky);
  const BlasRuntime r = blas_runtime();
  if (r.vendor != "OpenBLAS") GTEST_SKIP() << "libblas.so.3 is not OpenBLAS here";
  EXPECT_FALSE(r.core.empty());
  EXPECT_FALSE(r.config.empty());
  const char* forced = std::getenv("OPENBLAS_CORETYPE");
  ASSERT_NE(forced, nullptr) << "the test runs with OPENBLAS_CORETYPE=Prescott";
  EXPECT_EQ(r.core, "Prescott");
}

TEST(BlasRuntime, NamesTheBetterKernelsForAGenericFallback) {
  if (blas_runtime().vendor != "OpenBLAS") GTEST_SKIP() << "libblas.so.3 is not OpenBLAS here";
  __builtin_cpu_init();
  std::string expected;
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
    expected = "SkylakeX";
  else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    expected = "Haswell";
  EXPECT_EQ(better_openblas_core(), expected);
}

TEST(SerialOpenMpScope, SwitchesParallelRegionsOffAndRestores) {
  ASSERT_TRUE(kLinksCholesky);
  auto get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  if (!get) GTEST_SKIP() << "no OpenMP runtime in this process (CHOLMOD built without OpenMP)";
  const int before = get();
  ASSERT_GT(before, 0);
  {
    const SerialOpenMpScope serial;
    EXPECT_EQ(get(), 0);
    {
      const SerialOpenMpScope inactive(false);
      EXPECT_EQ(get(), 0);
    }
    EXPECT_EQ(get(), 0);
  }
  EXPECT_EQ(get(), before);
}

}  // namespace
}  // namespace slamkit
