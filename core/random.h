// Deterministic randomness (design §3): every draw is a pure function of a seed and stable
// ids (a source patch, a vertex, a pixel, a sample counter) — never of time or thread order —
// so any thread reproduces any draw and a frame is the same bytes for any thread count.
#pragma once

#include <cstdint>

namespace penumbra::core {

// The golden-ratio increment of SplitMix64: spreads consecutive counters across the state.
inline constexpr uint64_t kGolden = 0x9E3779B97F4A7C15ull;

// SplitMix64 output function (Steele, Lea & Flood 2014, "Fast splittable pseudorandom
// number generators", OOPSLA) of the state `x`: a bijective 64-bit mix.
constexpr uint64_t splitmix64(uint64_t x) {
  x += kGolden;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// A uniform double in [0, 1) from the top 53 bits: exact, no libm.
constexpr double unitInterval(uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

// Draw number `counter` of the stream `key`.
constexpr double unitSample(uint64_t key, uint64_t counter) {
  return unitInterval(splitmix64(key + kGolden * counter));
}

}  // namespace penumbra::core
