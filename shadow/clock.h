// Time sources for the frame-rate controller (design.md §3): the kiosk reads a steady
// clock; the simulator reads a virtual clock advanced by a deterministic cost model, so a
// whole kiosk session replays to identical bytes.
#pragma once

#include <cstdint>
#include <vector>

namespace penumbra::shadow {

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

 private:
  Clock& clock_;
  int64_t lastNs_;
};

// A clock that only moves when told to. Used with CostModel in tests and the simulator.
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

// A deterministic model of one frame's rendering cost, all in integers so the simulated
// session is bit-exact on every platform:
//
//   ns = fixedNs + load * (passes * (perPassNs + perTexelPs * size^2 / 1000)
//                          + perPixelPs * shadowedPixels / 1000)
//
// following the shape of Gibson 2003 §9 (frame time grows with blending passes on top of a
// fixed shading/compositing part) and design.md §1 step 7 (each pass renders a size×size
// shadow map, then touches its shadowed pixels). `load` is a scripted factor, piecewise
// constant in time, that stands for the scene getting heavier or lighter (a load step); it
// scales the variable part only, so the fixed part stays what the controller was told.
class CostModel {
 public:
  struct LoadStep {
    int64_t atNs;       // in effect from this virtual time on
    uint32_t permille;  // load factor × 1000 (1000 = nominal)
  };

  struct Params {
    int64_t fixedNs = 0;
    int64_t perPassNs = 0;
    int64_t perTexelPs = 0;  // shadow-map texels (size^2) per pass, picoseconds each
    int64_t perPixelPs = 0;  // shadowed pixels in the frame, picoseconds each
  };

  // Throws std::invalid_argument for negative costs, or load steps that are not in strictly
  // increasing time order or have a zero factor.
  explicit CostModel(Params params, std::vector<LoadStep> loadSteps = {});

  // The load factor (‰) in effect at `nowNs`: 1000 before the first step.
  uint32_t loadPermilleAt(int64_t nowNs) const;

  // Cost of a frame that starts at `nowNs`. Saturates at INT64_MAX rather than wrapping.
  int64_t frameNs(int64_t nowNs, uint32_t passes, uint64_t shadowedPixels,
                  uint32_t shadowMapSize) const;

  const Params& params() const { return params_; }

 private:
  Params params_;
  std::vector<LoadStep> loadSteps_;
};

}  // namespace penumbra::shadow
