// Time sources (design §3): the frame-rate controller and the kiosk read time only through
// Clock. The board reads a steady clock; the simulator a virtual clock that its cost model
// advances, so a whole kiosk session replays to identical bytes.
#pragma once

#include <cstdint>

namespace penumbra::core {

// Nanoseconds since an arbitrary, fixed origin; never decreases.
class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t nowNanoseconds() = 0;
};

// std::chrono::steady_clock: monotonic, unaffected by wall-clock adjustments (a kiosk that
// syncs NTP mid-session must not see a frame take negative time).
class SteadyClock final : public Clock {
 public:
  int64_t nowNanoseconds() override;
};

// Wall time between laps, in milliseconds: the per-frame stage timings (CompositeStats,
// FrameLoop). Reads the steady clock unless given another one (tests: a VirtualClock).
class Stopwatch {
 public:
  Stopwatch();
  explicit Stopwatch(Clock& clock) : clock_(clock), lastNs_(clock.nowNanoseconds()) {}
  // Milliseconds since construction or since the previous lap.
  double lap();
  // The same in nanoseconds.
  int64_t lapNs();

 private:
  Clock& clock_;
  int64_t lastNs_;
};

// A clock that only moves when told to. The simulator advances it by its cost model
// (shadow::CostModel).
class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(int64_t startNs = 0);
  int64_t nowNanoseconds() override { return nowNs_; }
  // Moves time forward by `ns`. Throws std::invalid_argument for ns < 0 (a clock that runs
  // backwards would break the Clock contract) and std::overflow_error past INT64_MAX.
  void advance(int64_t ns);

 private:
  int64_t nowNs_;
};

}  // namespace penumbra::core
