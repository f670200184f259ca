#include "slamkit/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace slamkit {
namespace {

using Clock = std::chrono::steady_clock;

// One parallel_for call: chunks [c·chunk, min(n, (c+1)·chunk)) claimed through `next`.
struct Job {
  const std::function<void(std::size_t, std::size_t)>* fn;
  std::size_t n, chunk, num_chunks;
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;

  void run() {
    for (;;) {
      const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
      if (c >= num_chunks) return;
      const std::size_t begin = c * chunk;
      try {
        (*fn)(begin, std::min(n, begin + chunk));
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(num_chunks, std::memory_order_relaxed);  // skip the rest
      }
    }
  }
};

}  // namespace

// Protocol (all atomics sequentially consistent where it matters):
//   post:   current ← job; ++generation; wake sleepers.      finish: current ← null; wait active = 0.
//   worker: sees a new generation → ++active; job ← current; run it if any; −−active.
// A worker raises `active` before it reads `current`, and the caller clears `current` before
// it reads `active`, so the caller never returns (destroying the job on its stack) while a
// worker can still touch it.
struct ThreadPool::Impl {
  std::vector<std::thread> workers;
  std::atomic<Job*> current{nullptr};
  std::atomic<unsigned long> generation{0};
  std::atomic<int> active{0};
  std::atomic<int> sleepers{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::condition_variable wake;
  Clock::duration spin;
  std::once_flag started;

  void worker_loop() {
    unsigned long seen = 0;
    Clock::time_point last_job = Clock::now();
    while (!stop.load()) {
      const unsigned long g = generation.load();
      if (g != seen) {
        active.fetch_add(1);
        if (Job* job = current.load()) job->run();
        active.fetch_sub(1);
        seen = g;
        last_job = Clock::now();
      } else if (Clock::now() - last_job < spin) {
        std::this_thread::yield();  // poll, but give the core to any runnable thread
      } else {
        std::unique_lock<std::mutex> lock(mutex);
        sleepers.fetch_add(1);
        wake.wait(lock, [&] { return stop.load() || generation.load() != seen; });
        sleepers.fetch_sub(1);
        last_job = Clock::now();
      }
    }
  }
};

int ThreadPool::hardware_threads() {
  // Read once per process: libstdc++ reads /sys/devices/system/cpu/online on every call, and
  // every default pool asks.
  static const int n = [] {
    const unsigned c = std::thread::hardware_concurrency();
    return c == 0 ? 1 : static_cast<int>(c);
  }();
  return n;
}

const char* ThreadPool::backend() { return "std::thread pool"; }

ThreadPool::ThreadPool(int threads, double spin_seconds)
    : threads_(threads > 0 ? threads : hardware_threads()), impl_(std::make_unique<Impl>()) {
  impl_->spin = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(std::max(0.0, spin_seconds)));
  // The workers start with the first job that is split (parallel_for): a pool whose jobs are
  // all below their grain never has a thread polling next to the caller for CPU time.
}

ThreadPool::~ThreadPool() {
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stop.store(true);
  }
  impl_->wake.notify_all();
  for (std::thread& w : impl_->workers) w.join();
}

void ThreadPool::parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn,
                              std::size_t grain) const {
  if (n == 0) return;
  // About 8 chunks per thread: a late worker (a descheduled vCPU) leaves its share to others.
  const std::size_t per_chunk = (n + 8 * static_cast<std::size_t>(threads_) - 1) / (8 * static_cast<std::size_t>(threads_));
  const std::size_t chunk = std::max<std::size_t>({grain, per_chunk, 1});
  if (threads_ == 1 || n <= chunk) {
    fn(0, n);
    return;
  }
  Impl& p = *impl_;
  std::call_once(p.started, [&] {
    p.workers.reserve(static_cast<std::size_t>(threads_ - 1));
    for (int t = 1; t < threads_; ++t) p.workers.emplace_back([this] { impl_->worker_loop(); });
  });
  Job job;
  job.fn = &fn;
  job.n = n;
  job.chunk = chunk;
  job.num_chunks = (n + chunk - 1) / chunk;
  p.current.store(&job);
  p.generation.fetch_add(1);
  if (p.sleepers.load() > 0) {
    { const std::lock_guard<std::mutex> lock(p.mutex); }  // a sleeper is either waiting or sees the new generation
    p.wake.notify_all();
  }
  job.run();
  p.current.store(nullptr);
  while (p.active.load() != 0) std::this_thread::yield();
  if (job.error) std::rethrow_exception(job.error);
}

}  // namespace slamkit
