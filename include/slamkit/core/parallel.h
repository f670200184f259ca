// ThreadPool: the one place slamkit runs work in parallel (oneTBB when available, else
// serially). parallel_for hands out disjoint index ranges; callers write each output from
// exactly one range and never reduce across ranges, so results do not depend on the number
// of threads (bit-identical to a single-threaded run).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace slamkit {

class ThreadPool {
 public:
  /// threads ≤ 0: all hardware threads.
  explicit ThreadPool(int threads = 0);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return threads_; }
  /// Calls fn(begin, end) on disjoint ranges covering [0, n); ranges hold ≥ grain items.
  void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn,
                    std::size_t grain = 256) const;
  /// "oneTBB" or "serial".
  static const char* backend();
  static int hardware_threads();

 private:
  int threads_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamkit
