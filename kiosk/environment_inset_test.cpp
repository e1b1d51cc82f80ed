// The HUD's view of the environment camera: each map pixel shows where its direction lies on
// the disc, and a light's dot where its direction is.
#include "kiosk/environment_inset.h"

#include <gtest/gtest.h>

namespace penumbra::kiosk {
namespace {

TEST(EnvironmentInset, MapPixelsAndLightsLandWhereTheirDirectionsAre) {
  constexpr uint32_t kSize = 96, kWidth = 200, kHeight = 120;
  envmap::HemisphereMap map;
  map.radiance = core::ImageF(envmap::kEnvmapCols, envmap::kEnvmapRows, 0.05f);
  // A lamp over a few map pixels around one direction.
  const uint32_t col = 100, row = 50;
  for (uint32_t r = row - 2; r <= row + 2; ++r)
    for (uint32_t c = col - 3; c <= col + 3; ++c)
      for (int k = 0; k < 3; ++k) map.radiance.pixel(c, r)[k] = 50.0f;
  const glm::dvec3 lamp = map.pixelCentre(col, row);
  envmap::DirectionalLight zenith;
  zenith.direction = glm::dvec3(0, 0, 1);
  EnvironmentInset inset(kSize);
  std::vector<uint8_t> rgba(size_t(kWidth) * kHeight * 4, 0);
  const int x0 = 10, y0 = 20;
  inset.draw(map, std::span(&zenith, 1), glm::dmat3(1.0), rgba, kWidth, kHeight, x0, y0);

  // Where the lamp must be: its disc point d.xy / √(1 + z), in inset pixels.
  const double s = 1.0 / std::sqrt(1.0 + lamp.z);
  const double ex = x0 + (lamp.x * s + 1.0) * 0.5 * kSize,
               ey = y0 + (lamp.y * s + 1.0) * 0.5 * kSize;
  double sx = 0, sy = 0, n = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const uint8_t* p = &rgba[4 * (size_t(y) * kWidth + x)];
      if (p[0] > 200 && p[1] > 200 && p[2] > 200) sx += x + 0.5, sy += y + 0.5, n += 1;
    }
  ASSERT_GT(n, 0);
  EXPECT_NEAR(sx / n, ex, 2.0);
  EXPECT_NEAR(sy / n, ey, 2.0);
  // The zenith light's dot at the disc's centre, yellow.
  const uint8_t* c = &rgba[4 * (size_t(y0 + kSize / 2) * kWidth + size_t(x0 + kSize / 2))];
  EXPECT_EQ(c[0], 255);
  EXPECT_EQ(c[1], 220);
  EXPECT_EQ(c[2], 0);
  // Outside the disc, nothing drawn.
  EXPECT_EQ(rgba[4 * (size_t(y0) * kWidth + size_t(x0))], 0);

  envmap::HemisphereMap small;
  small.radiance = core::ImageF(90, 30, 1.0f);
  EXPECT_THROW(inset.draw(small, {}, glm::dmat3(1.0), rgba, kWidth, kHeight, 0, 0),
               envmap::ToneMapError);
}

}  // namespace
}  // namespace penumbra::kiosk
