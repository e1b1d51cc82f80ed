// A minimal fork-join pool for tile and pass jobs (docs/pipeline-spec.md §8).
//
// parallelFor(n, fn) runs fn(0) ... fn(n-1), each exactly once, on the calling thread and
// the workers, and returns when all have finished. Which thread runs which index is not
// deterministic; callers make each index own its outputs, so the result is.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra::core {

class JobPool {
 public:
  explicit JobPool(int threads);  // threads >= 1, including the caller
  ~JobPool();
  JobPool(const JobPool&) = delete;
  JobPool& operator=(const JobPool&) = delete;

  // `fn(index, worker)`: worker in [0, threads()) identifies per-thread scratch space.
  // Threads claim `grain` consecutive indices at a time: each claim is an atomic on a
  // cache line the threads share, which costs more than a short job (a tile's finish).
  void parallelFor(size_t n, const std::function<void(size_t index, int worker)>& fn,
                   size_t grain = 1);
  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // How long a thread polls for the next job (or, the caller, for the last worker) before
  // it blocks. A frame makes three parallelFor calls a few hundred microseconds apart;
  // waking a blocked thread took tens of microseconds each time on the 2-core VMs here.
  static constexpr int64_t kSpinMicroseconds = 200;

 private:
  void workerLoop(int worker);
  void drain(int worker);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  // Written under mutex_ before generation_ is released; read after acquiring it.
  const std::function<void(size_t, int)>* job_ = nullptr;
  size_t jobSize_ = 0;
  size_t grain_ = 1;
  // On its own cache line: claims do not invalidate the fields every thread reads.
  alignas(64) std::atomic<size_t> next_{0};
  alignas(64) std::atomic<uint64_t> generation_{0};
  std::atomic<int> busy_{0};
  bool stop_ = false;  // under mutex_
};

}  // namespace penumbra::core
