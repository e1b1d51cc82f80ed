// Counter-based uniform variates for offline Monte Carlo stages (the ray-traced reference,
// reference/): a draw is a pure function of (key, counter), so any thread reproduces any
// draw (docs/design.md §3: randomness keyed by stable ids, never by thread order). The work
// split that goes with it is raster/job_pool.h, one work item owning its outputs.
#pragma once

#include <cstdint>

#include "shadow/intensity_transfer.h"

namespace penumbra::lighting {

// The golden-ratio increment of SplitMix64: spreads consecutive counters across the state.
inline constexpr uint64_t kGolden = 0x9E3779B97F4A7C15ull;

// A uniform double in [0, 1) from the top 53 bits: exact, no libm.
inline double unitInterval(uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

// Draw number `counter` of the stream `key`: a pure function of both, so any thread can
// reproduce any draw.
inline double unitSample(uint64_t key, uint64_t counter) {
  return unitInterval(shadow::splitmix64(key + kGolden * counter));
}

}  // namespace penumbra::lighting
