// Colour vocabulary: the 8-bit RGB triple every layer exchanges (tone-mapped vertex colours,
// intensity transfers S, pixels) and the one luminance weighting the project uses wherever a
// colour must become one number.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace penumbra::core {

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8&) const = default;
};

// Rec. 709 / sRGB luminance weights (ITU-R BT.709-6, item 3.2), summed in the order
// r, g, b: a fixed order, so the value is the same bytes on every ISA (design §3).
inline double luminance(const glm::dvec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}
inline float luminance(const glm::vec3& c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

}  // namespace penumbra::core
