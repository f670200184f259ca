#pragma once
// Heap policy for processes that run one estimation after another (the CLI, benchmarks).
//
// On the 2-core VM a fresh 4 KiB page costs 1.1-2 us to fault in (allocation and zeroing,
// measured with a plain touch loop and with MADV_POPULATE_WRITE alike), and a small pose graph's
// run touches ~270 of them: a quarter of its time. A 2 MiB transparent huge page costs 26-50 us,
// i.e. 0.05-0.1 us per 4 KiB. configure_process_heap() therefore
//   1. keeps freed memory in the heap (blocks below 4 MiB are not mmapped, up to 128 MiB of free
//      heap top is kept), so memory freed by one phase serves the next without new faults;
//   2. reserves `huge_reserve_bytes` of address space at the heap top and marks it
//      MADV_HUGEPAGE, so that the first allocations of the run are backed by huge pages
//      (address space only: nothing is touched here; a touched 2 MiB region counts fully in the
//      resident set, so resident memory may exceed the bytes in use by up to the reserve).
// Heap growth beyond the reserve and blocks above 4 MiB use ordinary pages. A library caller
// that wants the same calls it once at the start of main(). No-op outside glibc on Linux.
#include <cstddef>

namespace slamkit {

struct ProcessHeapReport {
  bool tuned = false;           // the malloc thresholds were set
  std::size_t huge_bytes = 0;   // bytes of heap address space marked for huge pages (0: none)
};

constexpr std::size_t kDefaultHugeHeapReserve = std::size_t{64} << 20;

ProcessHeapReport configure_process_heap(std::size_t huge_reserve_bytes = kDefaultHugeHeapReserve);

}  // namespace slamkit
