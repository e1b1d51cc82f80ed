#include "core/job_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
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

// More threads than cores, jobs shorter than a wake-up: most calls end before some workers
// run at all, so they arrive late, find the job closed (or a newer one) and must neither run
// an index of it nor be waited for. Every call still runs each index exactly once, and a
// late worker never sees another call's function (each call checks its own tag).
TEST(JobPool, LateWorkersSkipClosedJobs) {
  const int threads = 2 * static_cast<int>(std::max(2u, std::thread::hardware_concurrency()));
  JobPool pool(threads);
  std::vector<std::atomic<int>> runs(3);
  std::atomic<int> foreign{0}, onWorkers{0};
  for (int round = 0; round < 3000; ++round) {
    for (auto& r : runs) r.store(0);
    const int tag = round;
    pool.parallelFor(runs.size(), [&, tag](size_t i, int worker) {
      if (tag != round) foreign.fetch_add(1);
      if (worker != 0) onWorkers.fetch_add(1);
      runs[i].fetch_add(1);
    });
    for (size_t i = 0; i < runs.size(); ++i) ASSERT_EQ(runs[i].load(), 1) << "round " << round;
  }
  EXPECT_EQ(foreign.load(), 0);
  // And workers that do arrive in time join: index 0 holds its thread (up to a second) until
  // index 1 has run, so the two run on two threads, one of them a joined worker.
  std::atomic<bool> secondRan{false};
  pool.parallelFor(2, [&](size_t i, int worker) {
    if (worker != 0) onWorkers.fetch_add(1);
    if (i == 1) {
      secondRan.store(true);
      return;
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (!secondRan.load() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::yield();
    }
  });
  EXPECT_GT(onWorkers.load(), 0);
}

// threads == 0 asks for one thread per hardware thread (the offline stages' default).
TEST(JobPool, ZeroThreadsMeansHardwareConcurrency) {
  const JobPool pool(0);
  EXPECT_EQ(pool.threads(), static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
}

// On one thread (the inline path) the first exception ends the loop where it is thrown.
TEST(JobPool, OneThreadStopsAtTheFirstException) {
  JobPool pool(1);
  std::vector<int> runs(10, 0);
  try {
    pool.parallelFor(runs.size(), [&](size_t i, int) {
      ++runs[i];
      if (i == 3) throw std::runtime_error("item 3");
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 3");
  }
  EXPECT_EQ(runs, (std::vector<int>{1, 1, 1, 1, 0, 0, 0, 0, 0, 0}));
}

// A worker thread's exception reaches the caller (it must not end the process), the other
// threads stop claiming indices, and the pool runs the next job in full.
TEST(JobPool, WorkerExceptionIsRethrownOnTheCallerAndStopsTheRest) {
  for (int threads : {2, 4}) {
    JobPool pool(threads);
    constexpr size_t kItems = 1000;
    std::atomic<bool> thrown{false};
    std::atomic<int> startedAfterThrow{0};
    const auto body = [&](size_t i, int worker) {
      if (thrown.load()) {
        startedAfterThrow.fetch_add(1);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return;
      }
      if (worker == 0) {
        // The caller's first index waits for a worker's throw, so a worker throws first.
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (!thrown.load() && std::chrono::steady_clock::now() < deadline) {
          std::this_thread::sleep_for(std::chrono::microseconds(50));
        }
        return;
      }
      if (!thrown.exchange(true)) throw std::runtime_error("item " + std::to_string(i));
    };
    try {
      pool.parallelFor(kItems, body);
      ADD_FAILURE() << "no exception, threads " << threads;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("item ", 0), 0u) << e.what();
    }
    // A pool that ignored the exception would start all ~1000 remaining indices; a stopped
    // one starts those claimed before the stop: one per other thread, a few more only if
    // the throwing thread is descheduled between its throw and the stop.
    EXPECT_LT(startedAfterThrow.load(), int(kItems / 10)) << "threads " << threads;

    std::atomic<size_t> runs{0};
    pool.parallelFor(kItems, [&](size_t, int) { runs.fetch_add(1); });
    EXPECT_EQ(runs.load(), kItems) << "threads " << threads;
  }
}

// Every index throwing, on every thread at once: exactly one exception comes back (the
// others are dropped), from the caller's share or a worker's, and nothing deadlocks.
TEST(JobPool, ManyExceptionsRethrowOne) {
  JobPool pool(4);
  for (int round = 0; round < 50; ++round) {
    for (size_t grain : {size_t{1}, size_t{16}}) {
      EXPECT_THROW(
          pool.parallelFor(
              256, [](size_t i, int) { throw std::out_of_range(std::to_string(i)); }, grain),
          std::out_of_range)
          << "round " << round;
    }
  }
  std::atomic<int> runs{0};
  pool.parallelFor(8, [&](size_t, int) { runs.fetch_add(1); });
  EXPECT_EQ(runs.load(), 8);
}

}  // namespace
}  // namespace penumbra::core
