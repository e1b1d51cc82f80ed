// Byte statistics between two RGBA8 frames of the same size (GL replay vs Renderer).
#pragma once

#include <cstdint>
#include <span>

namespace penumbra::gl {

struct ImageDiff {
  uint64_t bytes = 0;
  double identicalByteShare = 0;  // bytes equal / all bytes (alpha included)
  int maxAbsDiff = 0;             // over all bytes
  double meanAbsDiff = 0;         // over all bytes
  // Max over bytes of the smallest |a - b'| where b' ranges over the same channel of the
  // 3x3 neighbourhood in `b`: differences a one-pixel edge shift explains score 0-ish.
  int maxAbsDiffShiftTolerant = 0;
  uint64_t differingPixels = 0;  // pixels with any differing byte
};

// `a`, `b`: width*height*4 bytes each. Throws std::invalid_argument on size mismatch.
ImageDiff compareImages(std::span<const uint8_t> a, std::span<const uint8_t> b, uint32_t width,
                        uint32_t height);

}  // namespace penumbra::gl
