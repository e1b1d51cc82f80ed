#include "core/job_pool.h"

#include <algorithm>
#include <chrono>

namespace penumbra::core {
namespace {

void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

// Polls `ready` for up to JobPool::kSpinMicroseconds; true once it holds.
template <class Ready>
bool spinUntil(Ready&& ready) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::microseconds(JobPool::kSpinMicroseconds);
  for (;;) {
    for (int i = 0; i < 64; ++i) {
      if (ready()) return true;
      cpuRelax();
    }
    if (Clock::now() >= deadline) return ready();
  }
}

}  // namespace

JobPool::JobPool(int threads) {
  for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { workerLoop(w); });
}

JobPool::~JobPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    // Spinning workers see a new generation and then find stop_ under the lock.
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void JobPool::drain(int worker) {
  const std::function<void(size_t, int)>& job = *job_;
  const size_t size = jobSize_, grain = grain_;
  for (size_t first = next_.fetch_add(grain); first < size; first = next_.fetch_add(grain)) {
    const size_t last = std::min(size, first + grain);
    for (size_t i = first; i < last; ++i) job(i, worker);
  }
}

void JobPool::workerLoop(int worker) {
  uint64_t seen = 0;
  for (;;) {
    spinUntil([&] { return generation_.load(std::memory_order_acquire) != seen; });
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return generation_.load(std::memory_order_relaxed) != seen; });
      if (stop_) return;
      seen = generation_.load(std::memory_order_relaxed);
    }
    drain(worker);
    // The last worker out tells the caller, under the lock: a caller that found busy_ != 0
    // holds the lock until it waits, so this notify cannot fall between its test and wait.
    if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      done_.notify_one();
    }
  }
}

void JobPool::parallelFor(size_t n, const std::function<void(size_t, int)>& fn, size_t grain) {
  if (workers_.empty() || n <= 1) {
    for (size_t i = 0; i < n; ++i) fn(i, 0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    jobSize_ = n;
    grain_ = std::max<size_t>(1, grain);
    next_.store(0);
    busy_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  drain(0);
  if (!spinUntil([&] { return busy_.load(std::memory_order_acquire) == 0; })) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return busy_.load(std::memory_order_acquire) == 0; });
  }
  job_ = nullptr;
}

}  // namespace penumbra::core
