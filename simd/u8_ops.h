// Exact 8-bit arithmetic: the product that stands in for a texture combiner's modulate
// and the saturating subtract that stands in for GL_FUNC_REVERSE_SUBTRACT blending
// (Gibson 2003 §7, docs/pipeline-spec.md §7).
//
// Scalar definitions are here; vector versions of the same formulas are in
// simd/u8_ops-inl.h for kernels compiled per target. u8OpsFor(isa) gives array kernels on
// every target so tests can compare all 65,536 pairs byte for byte.
#pragma once

#include <cstddef>
#include <cstdint>

#include "simd/targets.h"

namespace penumbra::simd {

// round(a * b / 255), exact for all 65,536 pairs (tests/u8_ops_test.cpp checks them all).
// Why this form: a*b/255 = a*b*257/65535 and 257/65536 differs from 257/65535 by less
// than 2^-16 relative, so adding 0x8080 (= half of 65536 plus the 128/65536 correction)
// before the shift rounds to nearest with no ties for any 8-bit inputs.
constexpr uint8_t productU8(uint8_t a, uint8_t b) {
  return static_cast<uint8_t>((uint32_t{a} * b * 257u + 0x8080u) >> 16);
}

// Fixed-point accumulation (docs/pipeline-spec.md §8): one pass's masked amount in units of
// 1/256 level, S·W/65536 rounded half up, for S in 8.8 levels (at most 65280) and the
// occluded weight W in [0, 65536]. S·W + 32768 < 2^32, so u32 arithmetic is exact;
// W = 65536 (the umbra) gives exactly S.
constexpr uint32_t fineAmount(uint32_t s, uint32_t w) {
  return (s * w + 32768u) >> 16;
}

// A pixel's summed 8.8 amounts back to whole levels: round(sum / 256), ties up.
constexpr uint32_t fixed8_8Levels(uint32_t sum) {
  return (sum + 128u) >> 8;
}

constexpr uint8_t subtractSaturateU8(uint8_t a, uint8_t b) {
  return a > b ? static_cast<uint8_t>(a - b) : uint8_t{0};
}

// dst = max(dst - round(s * m / 255), 0): one masked shadow subtraction of one channel.
constexpr uint8_t subtractMaskedU8(uint8_t dst, uint8_t s, uint8_t m) {
  return subtractSaturateU8(dst, productU8(s, m));
}

// The same operations over arrays, compiled for one target.
struct U8Ops {
  void (*product)(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n);
  void (*subtractSaturate)(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n);
  void (*subtractMasked)(uint8_t* dst, const uint8_t* s, const uint8_t* m, size_t n);
};

// Kernels for `isa`; the caller checks isSupported(isa) first.
const U8Ops& u8OpsFor(Isa isa);

}  // namespace penumbra::simd
