// ThreadPool: the one place slamkit runs work in parallel. parallel_for hands out disjoint
// index ranges; callers write each output from exactly one range and never reduce across
// ranges, so results do not depend on the number of threads (bit-identical to one thread).
//
// An optimizer alternates short parallel phases (linearization, ~1 ms) with a serial one
// (the factorization, 5–100 ms). Workers that went to sleep during the serial phase take
// about a millisecond to wake up on a virtual machine, which costs more than the parallel
// phase saves (measured with oneTBB: a 0.15 ms parallel_for took 1.4 ms after 8 ms of serial
// work). So the workers here stay awake between jobs: they poll, yielding the core to any
// other runnable thread, for `spin_seconds` after their last job, then block until the next.
// The pool's threads start with its first split job and live as long as the pool (an optimizer
// creates one per run): phases below their grain run on the caller and wake no one.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace slamkit {

class ThreadPool {
 public:
  /// threads ≤ 0: all hardware threads. Workers poll for `spin_seconds` after a job, then sleep.
  explicit ThreadPool(int threads = 0, double spin_seconds = 0.2);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return threads_; }
  /// Calls fn(begin, end) on disjoint ranges covering [0, n), each of at least `grain`
  /// items (but the last), on the calling thread and the workers; returns when all are
  /// done. An exception thrown by fn is rethrown here (the remaining ranges are skipped).
  /// Not reentrant: fn must not call parallel_for on the same pool.
  void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn,
                    std::size_t grain = 256) const;
  /// The implementation's name, for summaries.
  static const char* backend();
  static int hardware_threads();

 private:
  int threads_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamkit
