// Shared by the live-lighting tests: small synthetic environments with known structure (a sky
// gradient and a bright window), and the angle between two directions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "envmap/directional_light.h"
#include "envmap/hemisphere_map.h"

namespace penumbra::envmap::testutil {

inline HemisphereMap uniformMap(glm::vec3 rgb, uint32_t cols = kEnvmapCols,
                                uint32_t rows = kEnvmapRows) {
  HemisphereMap map{core::ImageF(cols, rows)};
  for (uint32_t y = 0; y < rows; ++y)
    for (uint32_t x = 0; x < cols; ++x) {
      float* p = map.radiance.pixel(x, y);
      p[0] = rgb.r, p[1] = rgb.g, p[2] = rgb.b;
    }
  return map;
}

// A bluish sky brighter towards the zenith and a warm window (a block of pixels) of radiance
// `window` around azimuth column `windowCol`, rows 40–59 (zenith angle about 50–65°).
inline HemisphereMap windowMap(float window = 40.0f, uint32_t windowCol = 90) {
  HemisphereMap map = uniformMap({0, 0, 0});
  for (uint32_t y = 0; y < kEnvmapRows; ++y)
    for (uint32_t x = 0; x < kEnvmapCols; ++x) {
      float* p = map.radiance.pixel(x, y);
      const float sky = 1.0f - 0.5f * float(y) / kEnvmapRows;
      p[0] = 0.6f * sky, p[1] = 0.8f * sky, p[2] = 1.0f * sky;
      const uint32_t dx = std::min((x + kEnvmapCols - windowCol) % kEnvmapCols,
                                   (windowCol + kEnvmapCols - x) % kEnvmapCols);
      if (dx < 20 && y >= 40 && y < 60) p[0] = window, p[1] = 0.9f * window, p[2] = 0.7f * window;
    }
  return map;
}

// Angle between two directions, in degrees (for test messages and bounds only).
inline double angleDegrees(const glm::dvec3& a, const glm::dvec3& b) {
  const double c = glm::dot(glm::normalize(a), glm::normalize(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

}  // namespace penumbra::envmap::testutil
