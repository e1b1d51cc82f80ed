#include "envmap/live_lights.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "envmap/envmap_test_util.h"

namespace penumbra::envmap {
namespace {

// Options under which clustering is the identity: as many lights as samples, and a cluster
// radius (c_f · arcsin √(2/Q)) far below the closest pair of relaxed Halton points, so lights()
// shows the rescaled prefix itself.
LiveLightsOptions unclusteredOptions(uint32_t samples) {
  LiveLightsOptions o;
  o.samples = samples;
  o.maxLights = samples;
  o.clusterCorrection = 1e-3;
  return o;
}

// The y-up world: environment x → world x, environment y → world −z, the zenith → world +y.
glm::dmat3 yUpFrame() {
  return glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
}

void expectLightsCarry(const LightSet& lights, const glm::dvec3& total, const std::string& what) {
  const glm::dvec3 sum = totalPower(lights);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(sum[c], total[c], 1e-12 * total[c]) << what << ", channel " << c;
}

TEST(LiveLights, PrefixSampleCountFollowsTheBudget) {
  EXPECT_EQ(prefixSampleCount(300, 72, 72), 300u);    // the full budget: every sample
  EXPECT_EQ(prefixSampleCount(300, 72, 1000), 300u);  // clamped to Q
  EXPECT_EQ(prefixSampleCount(300, 72, 36), 150u);    // half the passes, half the prefix
  EXPECT_EQ(prefixSampleCount(300, 72, 1), 5u);       // ⌈300/72⌉
  EXPECT_EQ(prefixSampleCount(300, 72, 5), 21u);      // ⌈1500/72⌉ = ⌈20.83⌉
  EXPECT_EQ(prefixSampleCount(10, 10, 3), 3u);
  EXPECT_EQ(prefixSampleCount(7, 1, 1), 7u);
  EXPECT_THROW(prefixSampleCount(300, 72, 0), std::invalid_argument);
  EXPECT_THROW(prefixSampleCount(10, 11, 1), std::invalid_argument);
}

// A uniform environment: with clustering the identity, every light has the same power (the
// map's total / count) and the lights spread evenly: 4 equal-solid-angle z bands × 4 azimuth
// sectors hold 64/16 = 4 ± 2 lights each. With the default options the clusters of 300
// samples into at most 72 lights keep the total, and their power-weighted mean direction is
// the uniform hemisphere's, (0, 0, ½).
TEST(LiveLights, UniformMapGivesEqualPowerLightsOverTheHemisphere) {
  const HemisphereMap map = testutil::uniformMap({1.0f, 0.5f, 0.25f});
  const glm::dvec3 total = glm::dvec3(1.0, 0.5, 0.25) * (2 * std::numbers::pi);
  LiveLights live(unclusteredOptions(64));
  live.update(map);
  const LightSet& lights = live.lights(64);
  ASSERT_EQ(lights.size(), 64u);
  std::array<int, 16> cells{};
  for (const DirectionalLight& light : lights) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(light.power[c], total[c] / 64, 1e-12 * total[c]);
    EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-15);
    const double azimuth = std::atan2(light.direction.y, light.direction.x) + std::numbers::pi;
    const int sector = std::min(3, int(azimuth / (2 * std::numbers::pi) * 4));
    ++cells[std::min(3, int(light.direction.z * 4)) * 4 + sector];
  }
  for (int k = 0; k < 16; ++k) EXPECT_NEAR(cells[k], 4, 2) << "cell " << k;

  LiveLights clustered{LiveLightsOptions{}};
  clustered.update(map);
  const LightSet& q72 = clustered.lights(72);
  EXPECT_LE(q72.size(), 72u);
  EXPECT_GE(q72.size(), 36u);
  expectLightsCarry(q72, total, "72 clusters");
  glm::dvec3 mean(0.0);
  double smallest = 1e300, largest = 0;
  for (const DirectionalLight& light : q72) {
    mean += light.power.r / total.r * light.direction;
    smallest = std::min(smallest, light.power.r), largest = std::max(largest, light.power.r);
  }
  EXPECT_NEAR(mean.x, 0.0, 0.03);
  EXPECT_NEAR(mean.y, 0.0, 0.03);
  EXPECT_NEAR(mean.z, 0.5, 0.03);
  // Greedy clusters are unequal (the paper, §4.3: "the light sources have unequal power after
  // the clustering"), but of a few samples each (measured: 1 to 17 of the 300, in 39 clusters).
  const double sample = total.r / 300;
  std::printf("uniform map: %zu clusters of %.0f to %.0f samples, mean (%.4f, %.4f, %.4f)\n",
              q72.size(), smallest / sample, largest / sample, mean.x, mean.y, mean.z);
  EXPECT_LE(largest, 24 * sample);
  EXPECT_GE(smallest, 0.99 * sample);
}

// Havran 2005 §3.2: the light count adapts along the Halton prefix, so a smaller budget's
// lights are a prefix of a larger one's: the same ids and the same directions; only the powers
// change (each prefix carries the whole filtered total).
TEST(LiveLights, SmallerBudgetsUseAPrefixOfTheSameFilteredSamples) {
  LiveLights live(unclusteredOptions(100));
  for (int frame = 0; frame < 3; ++frame) {  // through the filter's history too
    live.update(testutil::windowMap(40.0f + 5.0f * float(frame), 90 + 3 * uint32_t(frame)));
    const LightSet all = live.lights(100);  // a copy: lights() reuses its cache entries
    ASSERT_EQ(all.size(), 100u);
    for (size_t k : {1u, 10u, 37u, 99u}) {
      const LightSet& some = live.lights(k);
      ASSERT_EQ(some.size(), k);
      for (size_t i = 0; i < k; ++i) {
        EXPECT_EQ(some[i].id, all[i].id);
        EXPECT_EQ(some[i].id, i + 1);
        EXPECT_LT(glm::length(some[i].direction - all[i].direction), 1e-12)
            << "frame " << frame << ", light " << i << " of " << k;
      }
      expectLightsCarry(some, live.totalPower(), "prefix of " + std::to_string(k));
    }
  }

  // The same with clustering: every budget's clusters are seeded within its own prefix, and
  // the prefix before clustering is the filtered samples themselves, bit for bit.
  LiveLights clustered{LiveLightsOptions{}};
  clustered.update(testutil::windowMap());
  const LightSet& filtered = clustered.filtered();
  ASSERT_EQ(filtered.size(), 300u);
  for (size_t count : {1u, 5u, 24u, 72u}) {
    const uint32_t n = prefixSampleCount(300, 72, count);
    const LightSet prefix = rescaledPrefix(filtered, n, clustered.totalPower());
    ASSERT_EQ(prefix.size(), n);
    for (uint32_t i = 0; i < n; ++i) {
      EXPECT_EQ(prefix[i].id, filtered[i].id);
      EXPECT_EQ(prefix[i].direction, filtered[i].direction);
    }
    const LightSet& lights = clustered.lights(count);
    EXPECT_LE(lights.size(), count);
    for (const DirectionalLight& light : lights) EXPECT_LE(light.id, n) << "budget " << count;
  }
}

// Energy: whatever the budget, the lights carry the filtered total power × radianceScale.
TEST(LiveLights, LightsCarryTheFilteredTotalTimesTheScale) {
  LiveLightsOptions options;
  options.radianceScale = 2.5;
  LiveLights live(options);
  EXPECT_EQ(live.totalPower(), glm::dvec3(0.0));
  for (int frame = 0; frame < 5; ++frame) {
    live.update(testutil::windowMap(40.0f * float(1 + frame)));  // brightening: the FIR lags
    for (size_t count : {1u, 2u, 7u, 30u, 72u, 500u}) {
      const LightSet& lights = live.lights(count);
      EXPECT_LE(lights.size(), std::min<size_t>(count, 72));
      expectLightsCarry(lights, live.totalPower(),
                        "frame " + std::to_string(frame) + ", budget " + std::to_string(count));
    }
  }
  // The filtered total of a brightening sequence stays below this frame's map (delay 4).
  EnvmapDistribution last(testutil::windowMap(200.0f));
  EXPECT_LT(live.totalPower().r, 2.5 * last.totalPower().r);
  EXPECT_GT(live.totalPower().r, 0.0);
}

// toWorld: the y-up frame sends the zenith to world +y; every light is the environment-frame
// light with (x, y, z) → (x, z, −y).
TEST(LiveLights, ToWorldMapsTheZenithToWorldUp) {
  HemisphereMap map = testutil::uniformMap({0.01f, 0.01f, 0.01f});
  for (uint32_t row = 0; row < 4; ++row)  // u < 4/90: within 17.3° of the zenith
    for (uint32_t col = 0; col < map.cols(); ++col)
      for (int c = 0; c < 3; ++c) map.radiance.pixel(col, row)[c] = 1000.0f;
  LiveLightsOptions world;
  world.toWorld = yUpFrame();
  LiveLights up(world), env{LiveLightsOptions{}};
  up.update(map);
  env.update(map);
  const LightSet& a = up.lights(72);
  const LightSet& b = env.lights(72);
  ASSERT_EQ(a.size(), b.size());
  // The brightest light (most of the map's power is in the cap) points up.
  const DirectionalLight* brightest = &a[0];
  for (const DirectionalLight& light : a)
    if (light.power.g > brightest->power.g) brightest = &light;
  EXPECT_GT(brightest->direction.y, std::cos(20 * std::numbers::pi / 180));
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    EXPECT_EQ(a[i].power, b[i].power);
    const glm::dvec3 expected(b[i].direction.x, b[i].direction.z, -b[i].direction.y);
    EXPECT_LT(glm::length(a[i].direction - expected), 1e-14) << "light " << i;
    EXPECT_NEAR(glm::length(a[i].direction), 1.0, 1e-15);
  }
}

// A constant environment: the filter's history fills with the same frame, so the lights are the
// same bits every frame from the first on.
TEST(LiveLights, ConstantMapGivesTheSameLightsEveryFrame) {
  LiveLights live{LiveLightsOptions{}};
  const HemisphereMap map = testutil::windowMap();
  live.update(map);
  const LightSet first72 = live.lights(72), first9 = live.lights(9);
  const glm::dvec3 firstTotal = live.totalPower();
  EnvmapDistribution distribution(map);
  expectLightsCarry(first72, distribution.totalPower(), "first frame");
  for (int frame = 1; frame < 12; ++frame) {
    live.update(map);
    EXPECT_EQ(live.updates(), uint64_t(frame + 1));
    EXPECT_EQ(live.totalPower(), firstTotal);
    for (const auto& [count, reference] :
         {std::pair<size_t, const LightSet*>{72, &first72}, {9, &first9}}) {
      const LightSet& now = live.lights(count);
      ASSERT_EQ(now.size(), reference->size());
      for (size_t i = 0; i < now.size(); ++i) {
        EXPECT_EQ(now[i].id, (*reference)[i].id);
        EXPECT_EQ(now[i].direction, (*reference)[i].direction) << "frame " << frame;
        EXPECT_EQ(now[i].power, (*reference)[i].power) << "frame " << frame;
      }
    }
  }
}

void constructLiveLights(const LiveLightsOptions& options) {
  const LiveLights live(options);
  EXPECT_FALSE(live.ready());
}

TEST(LiveLights, InvalidOptionsAreRefused) {
  auto with = [](auto change) {
    LiveLightsOptions o;
    change(o);
    return o;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(constructLiveLights(with([](auto& o) { o.samples = 0; })), std::invalid_argument);
  EXPECT_THROW(constructLiveLights(with([](auto& o) { o.samples = kMaxLiveSamples + 1; })),
               std::invalid_argument);
  EXPECT_THROW(constructLiveLights(with([](auto& o) { o.maxLights = 0; })), std::invalid_argument);
  EXPECT_THROW(constructLiveLights(with([](auto& o) { o.maxLights = 301; })),
               std::invalid_argument);
  for (double bad : {0.0, -1.0, nan, inf}) {
    EXPECT_THROW(constructLiveLights(with([&](auto& o) { o.radianceScale = bad; })),
                 std::invalid_argument)
        << bad;
    EXPECT_THROW(constructLiveLights(with([&](auto& o) { o.clusterCorrection = bad; })),
                 std::invalid_argument)
        << bad;
  }
  EXPECT_THROW(constructLiveLights(with([](auto& o) { o.toWorld = glm::dmat3(2.0); })),
               std::invalid_argument);
  EXPECT_THROW(constructLiveLights(with([](auto& o) { o.toWorld[1][0] = 1e-6; })),  // a shear
               std::invalid_argument);
  EXPECT_THROW(constructLiveLights(with([&](auto& o) { o.toWorld[2][2] = nan; })),
               std::invalid_argument);
  EXPECT_NO_THROW(constructLiveLights(with([](auto& o) { o.toWorld = yUpFrame(); })));
  EXPECT_NO_THROW(constructLiveLights(with([](auto& o) {
    o.samples = 5, o.maxLights = 5, o.toWorld[1][0] = 1e-12;  // within the tolerance
  })));
}

// Before the first frame there are no lights; a bad frame is named and changes nothing.
TEST(LiveLights, LightsBeforeTheFirstUpdateAndBadMapsAreRefused) {
  LiveLights live{LiveLightsOptions{}};
  EXPECT_FALSE(live.ready());
  EXPECT_THROW(live.lights(10), std::logic_error);
  HemisphereMap bad = testutil::uniformMap({1, 1, 1});
  bad.radiance.pixel(3, 7)[1] = -1.0f;
  try {
    live.update(bad, "env_0007.exr");
    FAIL() << "a negative radiance was accepted";
  } catch (const EnvmapError& e) {
    EXPECT_NE(std::string(e.what()).find("env_0007.exr"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(live.ready());
  EXPECT_THROW(live.lights(10), std::logic_error);

  live.update(testutil::windowMap());
  ASSERT_TRUE(live.ready());
  EXPECT_THROW(live.lights(0), std::invalid_argument);
  const LightSet before = live.lights(72);
  const glm::dvec3 total = live.totalPower();
  EXPECT_THROW(live.update(HemisphereMap{}, "empty.exr"), EnvmapError);
  EXPECT_THROW(live.update(bad, "env_0008.exr"), EnvmapError);
  EXPECT_EQ(live.updates(), 1u);
  EXPECT_EQ(live.totalPower(), total);
  ASSERT_EQ(live.lights(72).size(), before.size());
  for (size_t i = 0; i < before.size(); ++i)
    EXPECT_EQ(live.lights(72)[i].direction, before[i].direction);
  // And the next good frame goes on from there.
  live.update(testutil::windowMap());
  EXPECT_EQ(live.updates(), 2u);
}

// The cache: the same budget in the same frame is the same object; budgets above Q share Q's.
TEST(LiveLights, RepeatedCallsInAFrameAreCached) {
  LiveLights live{LiveLightsOptions{}};
  live.update(testutil::windowMap());
  const LightSet* first = &live.lights(40);
  EXPECT_EQ(&live.lights(40), first);
  EXPECT_EQ(&live.lights(72), &live.lights(1000));
  const LightSet copy = *first;
  live.update(testutil::windowMap(400.0f));  // ten times brighter: a new result
  const LightSet& next = live.lights(40);
  EXPECT_GT(totalPower(next).r, totalPower(copy).r);
}

}  // namespace
}  // namespace penumbra::envmap
