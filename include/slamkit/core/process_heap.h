#pragma once
// Heap policy for processes that run one estimation after another (the CLI, benchmarks).
//
// On the 2-core VM a fresh 4 KiB page costs 1.1-2 us to fault in (allocation and zeroing,
// measured with a plain touch loop and with MADV_POPULATE_WRITE alike), and a small pose graph's
// run touches ~270 of them: a quarter of its time. A 2 MiB transparent huge page costs 26-50 us
// when the hypervisor still backs it (0.05-0.1 us per 4 KiB), but 1.5-6 ms when the guest has
// reported it free to the host (free page reporting works on 2 MiB blocks, so after a few idle
// seconds most huge pages are cold; 4 KiB pages come from warm small blocks). 64 MiB of huge
// pages after an idle pause cost 50-113 ms against 22-30 ms of small pages (docs/pose_graph_profile.md).
// configure_process_heap() therefore
//   1. keeps freed memory in the heap (blocks below 4 MiB are not mmapped, up to 128 MiB of free
//      heap top is kept), so memory freed by one phase serves the next without new faults;
//   2. marks the first `huge_reserve_bytes` (default 4 MiB: two huge pages, enough for a small
//      graph's whole run, few enough that a cold one stays rare) of the heap's growth
//      MADV_HUGEPAGE (address space only: nothing is touched here).
// Growth beyond the reserve and blocks above 4 MiB use ordinary pages. A library caller that
// wants the same calls it once at the start of main(); later calls keep the first reserve. The
// environment variable SLAMKIT_HUGE_PAGES=0 makes the reserve 0 (thresholds only). No-op outside
// glibc on Linux.
#include <cstddef>

namespace slamkit {

struct ProcessHeapReport {
  bool tuned = false;           // the malloc thresholds were set
  std::size_t huge_bytes = 0;   // bytes of heap address space marked for huge pages (0: none)
};

constexpr std::size_t kDefaultHugeHeapReserve = std::size_t{4} << 20;

ProcessHeapReport configure_process_heap(std::size_t huge_reserve_bytes = kDefaultHugeHeapReserve);

}  // namespace slamkit
