// Colour vocabulary: the 8-bit RGB triple every layer exchanges (tone-mapped vertex colours,
// pixels), the 8.8 fixed-point triple of intensity transfers S, and the one luminance weighting the
// project uses wherever a colour must become one number.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace penumbra::core {

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8&) const = default;
};

// Levels in 8.8 fixed point (value / 256 levels, at most 255 * 256 = 65280): the intensity
// transfers S of the blending passes, which a whole level per pass would quantize too
// coarsely once a shadow is spread over many faint passes (docs/pipeline-spec.md §5).
struct Rgb16 {
  uint16_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb16&) const = default;
  // Whole levels (8-bit codes) in 8.8.
  static constexpr Rgb16 fromLevels(const Rgb8& c) {
    return {static_cast<uint16_t>(c.r << 8), static_cast<uint16_t>(c.g << 8),
            static_cast<uint16_t>(c.b << 8)};
  }
};
inline constexpr uint16_t kMaxFineLevel = 255 * 256;

// Rec. 709 / sRGB luminance weights (ITU-R BT.709-6, item 3.2), summed in the order
// r, g, b: a fixed order, so the value is the same bytes on every ISA (design §3).
inline double luminance(const glm::dvec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}
inline float luminance(const glm::vec3& c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

}  // namespace penumbra::core
