// A minimal fork-join pool for tile and pass jobs (docs/pipeline-spec.md §8) and for the
// offline stages' work items (lighting/, reference/).
//
// parallelFor(n, fn) runs fn(0) ... fn(n-1), each exactly once, on the calling thread and
// the workers, and returns when all have finished. Which thread runs which index is not
// deterministic; callers make each index own its outputs, so the result is (design §3: same
// bytes for any thread count).
//
// Exceptions: the first exception thrown by fn stops the remaining indices (threads claim
// no new ones; indices already claimed finish) and is rethrown on the caller once every
// thread has left the job. The pool stays usable.
//
// Per frame, the renderer keeps one pool for its lifetime: its three calls a frame are
// hundreds of microseconds apart. An offline stage (a gather, a transfer matrix, a reference
// image) runs for milliseconds to minutes and constructs a pool per call: starting the
// threads costs tens of microseconds.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra::core {

class JobPool {
 public:
  // `threads` includes the caller; 0 means std::thread::hardware_concurrency() (at least 1).
  explicit JobPool(int threads);
  ~JobPool();
  JobPool(const JobPool&) = delete;
  JobPool& operator=(const JobPool&) = delete;

  // `fn(index, worker)`: worker in [0, threads()) identifies per-thread scratch space.
  // Threads claim `grain` consecutive indices at a time: each claim is an atomic on a
  // cache line the threads share, which costs more than a short job (a tile's finish).
  // Not reentrant: fn must not call parallelFor on the same pool.
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
  // The job's first exception, under mutex_; the caller reads it after every joined worker left.
  std::exception_ptr error_;
  // On its own cache line: claims do not invalidate the fields every thread reads.
  alignas(64) std::atomic<size_t> next_{0};
  alignas(64) std::atomic<uint64_t> generation_{0};
  // Who works on the current job. The high 32 bits hold the job's generation (its low 32
  // bits); the low bits count the workers that joined it, plus kClosed once the caller has
  // drained it. A worker joins by incrementing an open entry of its own generation, so the
  // caller waits only for workers that joined (they hold claimed indices or are about to
  // find none): a worker the OS has not scheduled yet — a busy core — delays nothing.
  std::atomic<uint64_t> entry_{0};
  std::atomic<int> left_{0};  // joined workers that have finished the job
  bool stop_ = false;         // under mutex_
};

// fn(begin, end, worker) over [0, n) in chunks of `chunk` indices, on `pool`'s threads, or on
// the calling thread (worker 0) when `pool` is null or there is one chunk. The per-frame
// stages use it for per-vertex work: each index owns its outputs, so the bytes do not depend
// on the pool.
template <class Fn>
void forEachChunk(JobPool* pool, size_t n, size_t chunk, Fn&& fn) {
  const size_t chunks = (n + chunk - 1) / chunk;
  const auto run = [&](size_t c, int worker) {
    fn(c * chunk, c * chunk + chunk < n ? c * chunk + chunk : n, worker);
  };
  if (pool == nullptr || chunks < 2) {
    for (size_t c = 0; c < chunks; ++c) run(c, 0);
  } else {
    pool->parallelFor(chunks, run);
  }
}

}  // namespace penumbra::core
