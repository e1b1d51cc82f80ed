// The simulated board's cost of a frame (design §3): with a VirtualClock it makes a whole
// kiosk session, and the frame-rate controller's decisions in it, replay to identical bytes.
#pragma once

#include <cstdint>
#include <vector>

namespace penumbra::shadow {

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
