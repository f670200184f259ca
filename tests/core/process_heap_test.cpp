// configure_process_heap: the huge-page reserve sits at the heap top, 2 MiB aligned, and the
// allocations that follow are carved from it (own test executable: it changes the process heap).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "slamkit/core/process_heap.h"

namespace {

// The THPeligible flag of the mapping that holds `address` (/proc/self/smaps), -1 if unknown.
int thp_eligible_at(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    unsigned long lo = 0, hi = 0;
    char dash = 0;
    if (std::sscanf(line.c_str(), "%lx%c%lx ", &lo, &dash, &hi) == 3 && dash == '-') {
      inside = lo <= a && a < hi;
      continue;
    }
    int eligible = 0;
    if (inside && std::sscanf(line.c_str(), "THPeligible: %d", &eligible) == 1) return eligible;
  }
  return -1;
}

bool thp_enabled() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(f, s);
  return !s.empty() && s.find("[never]") == std::string::npos;
}

}  // namespace

TEST(ProcessHeap, ReserveIsAlignedAndServesTheNextAllocations) {
  const slamkit::ProcessHeapReport report = slamkit::configure_process_heap();
#if defined(__GLIBC__) && defined(__linux__)
  EXPECT_TRUE(report.tuned);
  if (report.huge_bytes == 0) GTEST_SKIP() << "no huge-page reserve (SLAMKIT_HUGE_PAGES=0, or a kernel without THP)";
  EXPECT_EQ(report.huge_bytes % (std::size_t{2} << 20), 0u);
  EXPECT_EQ(report.huge_bytes, slamkit::kDefaultHugeHeapReserve);
  // A second call keeps the first reserve (no second filler, no second range).
  EXPECT_EQ(slamkit::configure_process_heap().huge_bytes, report.huge_bytes);
  // A block larger than any free chunk left below the reserve comes from its start, at a 2 MiB
  // boundary (plus malloc's chunk header), and is usable.
  const std::size_t n = std::size_t{3} << 20;
  auto* block = static_cast<unsigned char*>(std::malloc(n));
  ASSERT_NE(block, nullptr);
  EXPECT_LT(reinterpret_cast<std::uintptr_t>(block) % (std::size_t{2} << 20), 64u);
  std::memset(block, 7, n);
  EXPECT_EQ(block[n - 1], 7);
  // Whether the kernel then backs it by huge pages depends on its free memory; that the range
  // may be is the reserve's doing.
  if (thp_enabled()) EXPECT_EQ(thp_eligible_at(block), 1);
  std::free(block);
  // Later allocations of every size keep working.
  std::vector<std::vector<double>> many;
  for (int i = 1; i < 2000; ++i) many.emplace_back(static_cast<std::size_t>(i * 37 % 5000), 1.0);
  for (const auto& v : many) EXPECT_TRUE(v.empty() || v.back() == 1.0);
#else
  EXPECT_FALSE(report.tuned);
#endif
}

TEST(ProcessHeap, ZeroReserveOnlySetsTheThresholds) {
  const slamkit::ProcessHeapReport report = slamkit::configure_process_heap(0);
  EXPECT_EQ(report.huge_bytes, 0u);
}
