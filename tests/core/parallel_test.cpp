#include "slamkit/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace slamkit {
namespace {

// Every index in [0, n) is visited exactly once, in ranges of at least `grain` (but the last).
void expect_exact_cover(const ThreadPool& pool, std::size_t n, std::size_t grain) {
  std::vector<std::atomic<int>> visits(n);
  std::mutex m;
  std::vector<std::pair<std::size_t, std::size_t>> ranges;
  pool.parallel_for(
      n,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) visits[i].fetch_add(1);
        const std::lock_guard<std::mutex> lock(m);
        ranges.emplace_back(b, e);
      },
      grain);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i << " of " << n;
  for (const auto& [b, e] : ranges)
    if (e != n) EXPECT_GE(e - b, grain);
}

TEST(ThreadPool, CoversEveryIndexOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    const ThreadPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (std::size_t n : {0, 1, 7, 255, 256, 257, 1000, 100003}) expect_exact_cover(pool, n, 64);
    expect_exact_cover(pool, 5000, 1);
  }
}

TEST(ThreadPool, WorkersReallyRunInParallel) {
  const ThreadPool pool(2);
  std::mutex m;
  std::set<std::thread::id> ids;
  std::atomic<int> inside{0};
  std::atomic<bool> overlapped{false};
  // Each range waits (up to 2 s) for a second thread to be inside at the same time.
  pool.parallel_for(
      16,
      [&](std::size_t, std::size_t) {
        {
          const std::lock_guard<std::mutex> lock(m);
          ids.insert(std::this_thread::get_id());
        }
        inside.fetch_add(1);
        const auto t0 = std::chrono::steady_clock::now();
        while (!overlapped && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(2))
          if (inside.load() >= 2) overlapped = true;
        inside.fetch_sub(1);
      },
      1);
  EXPECT_TRUE(overlapped.load());
  EXPECT_EQ(ids.size(), 2u);
}

TEST(ThreadPool, ManyShortJobsAfterWorkersFellAsleep) {
  // spin 0: workers block between jobs, so every job goes through the wake-up path.
  const ThreadPool sleepy(4, 0.0);
  std::vector<double> v(4096, 0.0);
  for (int job = 0; job < 2000; ++job) {
    if (job % 500 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    sleepy.parallel_for(v.size(), [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) v[i] += 1.0;
    }, 16);
  }
  for (double x : v) ASSERT_EQ(x, 2000.0);
}

TEST(ThreadPool, RethrowsTheExceptionOfARangeAndStaysUsable) {
  const ThreadPool pool(3);
  EXPECT_THROW(pool.parallel_for(
                   1000,
                   [](std::size_t b, std::size_t e) {
                     if (b <= 500 && 500 < e) throw std::runtime_error("range with 500");
                   },
                   10),
               std::runtime_error);
  expect_exact_cover(pool, 1000, 10);
}

TEST(ThreadPool, AllHardwareThreadsByDefault) {
  EXPECT_EQ(ThreadPool().threads(), ThreadPool::hardware_threads());
  EXPECT_EQ(ThreadPool(-1).threads(), ThreadPool::hardware_threads());
}

}  // namespace
}  // namespace slamkit
