#include "core/job_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace penumbra::core {
namespace {

// Every index runs exactly once, on a valid worker, for any size and grain.
TEST(JobPool, EveryIndexRunsOnceOnAValidWorker) {
  for (int threads : {1, 2, 3, 8}) {
    JobPool pool(threads);
    for (size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{17}, size_t{1000}}) {
      for (size_t grain : {size_t{0}, size_t{1}, size_t{7}, size_t{5000}}) {
        std::vector<std::atomic<int>> runs(n);
        std::atomic<int> badWorker{0};
        pool.parallelFor(
            n,
            [&](size_t i, int worker) {
              runs[i].fetch_add(1);
              if (worker < 0 || worker >= pool.threads()) badWorker.fetch_add(1);
            },
            grain);
        for (size_t i = 0; i < n; ++i) {
          ASSERT_EQ(runs[i].load(), 1) << "threads " << threads << " n " << n << " index " << i;
        }
        EXPECT_EQ(badWorker.load(), 0);
      }
    }
  }
}

// parallelFor returns only after every job finished, including jobs on other threads
// that outlast the caller's share (the spin wait must not return early).
TEST(JobPool, ReturnsAfterTheSlowestJob) {
  JobPool pool(2);
  for (int round = 0; round < 20; ++round) {
    std::atomic<int> finished{0};
    pool.parallelFor(2, [&](size_t i, int) {
      if (i == 1) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      finished.fetch_add(1);
    });
    ASSERT_EQ(finished.load(), 2) << "round " << round;
  }
}

// Back-to-back calls (the spinning path) and calls after the workers blocked (the
// sleeping path: longer than JobPool::kSpinMicroseconds apart) both complete.
TEST(JobPool, WakesSpinningAndSleepingWorkers) {
  JobPool pool(3);
  std::atomic<long> total{0};
  for (int round = 0; round < 200; ++round) {
    pool.parallelFor(64, [&](size_t i, int) { total.fetch_add(long(i)); });
  }
  for (int round = 0; round < 3; ++round) {
    std::this_thread::sleep_for(std::chrono::microseconds(3 * JobPool::kSpinMicroseconds));
    pool.parallelFor(64, [&](size_t i, int) { total.fetch_add(long(i)); });
  }
  EXPECT_EQ(total.load(), 203L * (63L * 64L / 2));
}

// A pool destroyed while its workers spin, or sleep, joins them.
TEST(JobPool, DestructionJoinsIdleWorkers) {
  for (int wait : {0, 1}) {
    std::atomic<int> runs{0};
    {
      JobPool pool(4);
      pool.parallelFor(8, [&](size_t, int) { runs.fetch_add(1); });
      if (wait) {
        std::this_thread::sleep_for(std::chrono::microseconds(3 * JobPool::kSpinMicroseconds));
      }
    }
    EXPECT_EQ(runs.load(), 8);
  }
}

}  // namespace
}  // namespace penumbra::core
