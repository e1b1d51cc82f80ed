#include "raster/job_pool.h"

#include <algorithm>

namespace penumbra::raster {

JobPool::JobPool(int threads) {
  for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { workerLoop(w); });
}

JobPool::~JobPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
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
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    drain(worker);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--busy_ == 0) done_.notify_one();
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
    busy_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  drain(0);
  std::unique_lock<std::mutex> lock(mutex_);
  done_.wait(lock, [&] { return busy_ == 0; });
  job_ = nullptr;
}

}  // namespace penumbra::raster
