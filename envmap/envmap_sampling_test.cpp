#include "envmap/envmap_sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "envmap/envmap_test_util.h"

namespace penumbra::envmap {
namespace {

using testutil::angleDegrees;

void expectPowerSumsTo(const LightSet& lights, const glm::dvec3& total) {
  const glm::dvec3 sum = totalPower(lights);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], total[c], 1e-12 * total[c]) << "channel " << c;
}

// A uniform environment: the warp is the identity, every light has the same RGB power, and
// the lights spread evenly: each of 4 equal-solid-angle z bands × 8 azimuth sectors holds
// 256/32 = 8 ± 3 lights, and no two lights are closer than 43% of the mean spacing
// √(2π/256) ≈ 9.0° (measured: 4.13°; the unrelaxed Halton points' closest pair is 3.39°, so
// this checks the Lloyd step's work).
TEST(EnvmapSampling, UniformEnvironmentGivesEvenlySpreadEqualPowerLights) {
  const HemisphereMap map = testutil::uniformMap({1.0f, 0.5f, 0.25f});
  const EnvmapDistribution distribution(map);
  const SamplePattern pattern(256);
  const LightSet lights = distribution.sample(pattern, 256);
  ASSERT_EQ(lights.size(), 256u);
  const glm::dvec3 total = distribution.totalPower();
  EXPECT_NEAR(total.r, 2 * 3.14159265358979323846, 1e-9);
  std::array<int, 32> cells{};
  for (const DirectionalLight& light : lights) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(light.power[c], total[c] / 256, 1e-12 * total[c]);
    const glm::dvec2& s = pattern.point(light.id);
    const glm::dvec3 unwarped = diskToHemisphere(concentricSquareToDisk(s.x, s.y));
    EXPECT_LT(angleDegrees(light.direction, unwarped), 1e-6) << "light " << light.id;
    const double azimuth =
        std::atan2(light.direction.y, light.direction.x) + 3.14159265358979323846;
    const int sector = std::min(7, int(azimuth / (2 * 3.14159265358979323846) * 8));
    ++cells[std::min(3, int(light.direction.z * 4)) * 8 + sector];
  }
  for (int k = 0; k < 32; ++k) EXPECT_NEAR(cells[k], 8, 3) << "cell " << k;
  double closest = 180;
  for (size_t i = 0; i < lights.size(); ++i)
    for (size_t j = i + 1; j < lights.size(); ++j)
      closest = std::min(closest, angleDegrees(lights[i].direction, lights[j].direction));
  const double spacing = std::sqrt(2 * 3.14159265358979323846 / 256) * 180 / 3.14159265358979323846;
  EXPECT_GT(closest, 0.43 * spacing)
      << "closest pair " << closest << "°, spacing " << spacing << "°";
}

// Energy: the lights' RGB powers add up to the map's, whatever the count.
TEST(EnvmapSampling, LightPowersSumToTheMapsPower) {
  const HemisphereMap map = testutil::windowMap();
  const EnvmapDistribution distribution(map);
  const SamplePattern pattern(300);
  for (uint32_t count : {1u, 7u, 72u, 300u})
    expectPowerSumsTo(distribution.sample(pattern, count), distribution.totalPower());
  // The window is ≈ 40× the sky over ≈ 2% of the solid angle: most lights go there.
  const LightSet lights = distribution.sample(pattern, 300);
  const auto inWindow = std::count_if(lights.begin(), lights.end(), [](const DirectionalLight& l) {
    return l.power.b < 0.8 * l.power.r;  // the window's warm colour
  });
  EXPECT_GT(inWindow, 150);
}

// Havran 2005 §3.2: the first k of n lights are the k-light set: the same ids and directions
// (bit for bit); only the common power share changes with the count.
TEST(EnvmapSampling, FirstKOfNLightsAreTheKLightSet) {
  const EnvmapDistribution distribution(testutil::windowMap());
  const SamplePattern pattern(300);
  const LightSet all = distribution.sample(pattern, 300);
  for (uint32_t k : {1u, 50u, 299u}) {
    const LightSet prefix = distribution.sample(pattern, k);
    ASSERT_EQ(prefix.size(), k);
    for (uint32_t i = 0; i < k; ++i) {
      EXPECT_EQ(prefix[i].id, all[i].id);
      EXPECT_EQ(prefix[i].direction, all[i].direction) << "light " << i << " of " << k;
    }
    expectPowerSumsTo(prefix, distribution.totalPower());
  }
  // And a larger pattern gives the same first lights only if it is the same pattern: the
  // relaxation is of the whole pattern (so the set is fixed once, for the largest count).
  const SamplePattern unrelaxed(300, false);
  EXPECT_NE(distribution.sample(unrelaxed, 10)[5].direction, all[5].direction);
}

// Continuity in the map (Havran 2005 §3.1): brightening a 10 × 5 patch of the window moves
// the lights in proportion to the change, without jumps: 0.1% moves none by more than 0.5°,
// and 1% moves them about 10× as far (measured: 0.36° and 3.7°, the largest motions being
// lights beside the window's sharp edge, where the interpolated CDF is steep). A jump (a light
// changing row without interpolation, a Halton index changing hands) would not scale.
TEST(EnvmapSampling, SmallChangeInTheMapMovesLightsALittle) {
  const SamplePattern pattern(300);
  const HemisphereMap base = testutil::windowMap();
  auto maxMotion = [&](float factor) {
    HemisphereMap changed = base;
    for (uint32_t y = 45; y < 50; ++y)
      for (uint32_t x = 80; x < 90; ++x)
        for (int c = 0; c < 3; ++c) changed.radiance.pixel(x, y)[c] *= factor;
    const LightSet a = EnvmapDistribution(base).sample(pattern, 300);
    const LightSet b = EnvmapDistribution(changed).sample(pattern, 300);
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i)
      worst = std::max(worst, angleDegrees(a[i].direction, b[i].direction));
    return worst;
  };
  const double tiny = maxMotion(1.0001f), small = maxMotion(1.001f), larger = maxMotion(1.01f);
  EXPECT_LT(small, 0.5) << "max light motion for a 0.1% change";
  EXPECT_GT(small, 0.0);
  EXPECT_NEAR(larger / small, 10.0, 3.0) << "motion " << small << "° and " << larger << "°";
  EXPECT_NEAR(small / tiny, 10.0, 3.0) << "motion " << tiny << "° and " << small << "°";
}

// Continuity of the warp between rows: rows alternate between energy in the left and the
// right half of the azimuths. Without interpolating neighbouring conditional CDFs the azimuth
// would jump by about half a turn at each row boundary; with it, a sweep of u in 20,000 steps
// of 2.5e-6 across several rows never moves the direction by more than 0.2°.
TEST(EnvmapSampling, WarpIsContinuousAcrossRowBoundaries) {
  HemisphereMap map = testutil::uniformMap({0.1f, 0.1f, 0.1f});
  for (uint32_t y = 0; y < kEnvmapRows; ++y)
    for (uint32_t x = 0; x < kEnvmapCols; ++x)
      if ((x < kEnvmapCols / 2) == (y % 2 == 0))
        for (int c = 0; c < 3; ++c) map.radiance.pixel(x, y)[c] = 5.0f;
  const EnvmapDistribution distribution(map);
  double worst = 0;
  glm::dvec3 previous = diskToHemisphere(distribution.warp({0.40, 0.3}));
  for (int step = 1; step <= 20000; ++step) {
    const glm::dvec3 d = diskToHemisphere(distribution.warp({0.40 + 0.05 * step / 20000, 0.3}));
    worst = std::max(worst, angleDegrees(previous, d));
    previous = d;
  }
  EXPECT_LT(worst, 0.2);
}

TEST(EnvmapSampling, BadMapsAreRefusedWithTheirNameAndPixel) {
  HemisphereMap map = testutil::uniformMap({1, 1, 1}, 8, 4);
  map.radiance.pixel(3, 2)[1] = -0.5f;
  try {
    EnvmapDistribution bad(map, "probe.exr");
    FAIL() << "negative radiance accepted";
  } catch (const EnvmapError& e) {
    EXPECT_NE(std::string(e.what()).find("probe.exr: pixel (3, 2)"), std::string::npos) << e.what();
  }
  map.radiance.pixel(3, 2)[1] = std::nanf("");
  EXPECT_THROW(EnvmapDistribution(map, "probe.exr"), EnvmapError);
  map.radiance.pixels.pop_back();
  EXPECT_THROW(EnvmapDistribution(map, "probe.exr"), EnvmapError);
  EXPECT_THROW(EnvmapDistribution(HemisphereMap{}, "empty"), EnvmapError);
  EnvmapDistribution ok(testutil::uniformMap({1, 1, 1}, 8, 4));
  EXPECT_THROW(ok.sample(SamplePattern(4), 5), EnvmapError);
  EXPECT_THROW(ok.update(map, "probe.exr"), EnvmapError);
  EXPECT_THROW(ok.sample(SamplePattern(4), 4), EnvmapError);  // left empty, not half-built
}

// A black map: no power, and the lights still have directions (the uniform ones).
TEST(EnvmapSampling, BlackMapGivesZeroPowerLights) {
  const EnvmapDistribution distribution(testutil::uniformMap({0, 0, 0}));
  const LightSet lights = distribution.sample(SamplePattern(16), 16);
  for (const DirectionalLight& light : lights) {
    EXPECT_EQ(light.power, glm::dvec3(0.0));
    EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace penumbra::envmap
