#include "slamkit/core/process_heap.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#if defined(__GLIBC__) && defined(__linux__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace slamkit {
namespace {
// The filler block below the huge-page range: held for the process's lifetime (reachable, so
// leak checkers do not report it); non-null once the reserve is in place.
void* heap_filler = nullptr;
std::size_t huge_reserved = 0;
}  // namespace

ProcessHeapReport configure_process_heap(std::size_t huge_reserve_bytes) {
  ProcessHeapReport report;
#if defined(__GLIBC__) && defined(__linux__)
  constexpr std::size_t kMmapThreshold = std::size_t{4} << 20, kTrimThreshold = std::size_t{128} << 20;
  constexpr std::size_t kHugePage = std::size_t{2} << 20, kDefaultTopPad = std::size_t{128} << 10;
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(kMmapThreshold));
  mallopt(M_TRIM_THRESHOLD, static_cast<int>(kTrimThreshold));
  report.tuned = true;
  if (const char* env = std::getenv("SLAMKIT_HUGE_PAGES"); env && std::string(env) == "0") huge_reserve_bytes = 0;
  // The reserve stays below the trim threshold with the block, or free() would hand it back.
  if (huge_reserve_bytes < kHugePage || huge_reserve_bytes + 4 * kHugePage > kTrimThreshold) return report;
  if (heap_filler) {  // a second call: the reserve made by the first stays as it is
    report.huge_bytes = huge_reserved;
    return report;
  }
  // A probe block larger than the heap's free top, allocated with a top pad of the reserve: the
  // main arena grows by brk to [probe, probe + probe size + reserve).
  constexpr std::size_t kProbe = std::size_t{1} << 20;
  mallopt(M_TOP_PAD, static_cast<int>(huge_reserve_bytes + 2 * kHugePage));  // room for the alignment
  void* probe = std::malloc(kProbe);
  mallopt(M_TOP_PAD, static_cast<int>(kDefaultTopPad));
  if (!probe) return report;
  const auto start = reinterpret_cast<std::uintptr_t>(probe);
  const auto heap_end = reinterpret_cast<std::uintptr_t>(sbrk(0));
  std::free(probe);  // back into the top chunk (below the trim threshold: kept)
  if (heap_end == static_cast<std::uintptr_t>(-1) || start >= heap_end || heap_end - start < huge_reserve_bytes + kProbe)
    return report;  // not the brk heap, or it did not grow
  // A huge page needs a whole aligned 2 MiB range that no small page has touched yet, and the
  // run's allocations are carved from the top upwards, starting at `probe`. So the range from
  // the first boundary past the probe's end (untouched: malloc writes chunk headers only at
  // chunk boundaries) is marked, then a filler block (kept for the process's lifetime; only its
  // boundary pages are touched) moves the top up to that boundary.
  constexpr std::uintptr_t kChunkHeader = 2 * sizeof(std::size_t);
  const std::uintptr_t begin = (start + kProbe + 4 * kChunkHeader + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t end = std::min(heap_end & ~(kHugePage - 1), begin + (huge_reserve_bytes & ~(kHugePage - 1)));
  if (end <= begin || madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE) != 0) return report;
  void* filler = std::malloc(begin - start - kChunkHeader);
  if (filler != probe) {  // served from elsewhere: the top did not move as planned
    std::free(filler);
    return report;
  }
  heap_filler = filler;
  report.huge_bytes = huge_reserved = end - begin;
#else
  (void)huge_reserve_bytes;
#endif
  return report;
}

}  // namespace slamkit
