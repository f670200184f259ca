#include "slamkit/core/parallel.h"

#include <thread>

#ifdef SLAMKIT_HAVE_TBB
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>
#endif

namespace slamkit {

struct ThreadPool::Impl {
#ifdef SLAMKIT_HAVE_TBB
  explicit Impl(int n) : arena(n) {}
  mutable tbb::task_arena arena;
#else
  explicit Impl(int) {}
#endif
};

int ThreadPool::hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

const char* ThreadPool::backend() {
#ifdef SLAMKIT_HAVE_TBB
  return "oneTBB";
#else
  return "serial";
#endif
}

ThreadPool::ThreadPool(int threads) : threads_(threads > 0 ? threads : hardware_threads()) {
#ifndef SLAMKIT_HAVE_TBB
  threads_ = 1;
#endif
  impl_ = std::make_unique<Impl>(threads_);
}

ThreadPool::~ThreadPool() = default;

void ThreadPool::parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn,
                              std::size_t grain) const {
  if (n == 0) return;
#ifdef SLAMKIT_HAVE_TBB
  if (threads_ > 1 && n > grain) {
    impl_->arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                        [&](const tbb::blocked_range<std::size_t>& r) { fn(r.begin(), r.end()); },
                        tbb::simple_partitioner());
    });
    return;
  }
#endif
  fn(0, n);
}

}  // namespace slamkit
