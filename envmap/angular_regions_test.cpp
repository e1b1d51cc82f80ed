#include "envmap/angular_regions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/random.h"
#include "envmap/envmap_sampling.h"
#include "envmap/envmap_test_util.h"

namespace penumbra::envmap {
namespace {

glm::dvec3 randomDirection(uint64_t i) {
  const double z = 2 * core::unitSample(11, 2 * i) - 1;
  const double phi = 2 * 3.14159265358979323846 * core::unitSample(11, 2 * i + 1);
  const double r = std::sqrt(1 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Havran 2005 §4.1: for 20,000 random normals, every light that lights the normal (N·L > 0)
// is in the list of the normal's region; the lists keep the lights' order (a prefix of the
// Halton lights stays a prefix); and they cull: the paper reports a practical speed-up of
// 1.6–1.8 with 200 regions, i.e. lists of 55–63% of the lights; asked here: under 70%.
TEST(AngularRegions, NoContributingLightIsCulledAndMostOthersAre) {
  const AngularRegions regions(200, 32);
  EXPECT_GT(regions.radiusDegrees(), 5.0);
  EXPECT_LT(regions.radiusDegrees(), 20.0);
  const LightSet lights =
      EnvmapDistribution(testutil::uniformMap({1, 1, 1})).sample(SamplePattern(300), 300);
  const auto lists = regions.assign(lights);
  ASSERT_EQ(lists.size(), 200u);
  size_t listed = 0;
  for (const auto& list : lists) {
    listed += list.size();
    for (size_t k = 1; k < list.size(); ++k) EXPECT_LT(list[k - 1], list[k]);
  }
  for (uint64_t n = 0; n < 20000; ++n) {
    const glm::dvec3 normal = randomDirection(n);
    const auto& list = lists[regions.regionOf(normal)];
    for (uint32_t i = 0; i < lights.size(); ++i) {
      if (glm::dot(normal, lights[i].direction) > 0) {
        ASSERT_TRUE(std::binary_search(list.begin(), list.end(), i))
            << "light " << i << " missing for normal " << n;
      }
    }
  }
  const double share = double(listed) / (200.0 * double(lights.size()));
  std::printf("angular regions: rho %.2f°, mean list %.1f%% of the lights (speed-up %.2f)\n",
              regions.radiusDegrees(), 100 * share, 1 / share);
  EXPECT_LT(share, 0.7);
  EXPECT_GT(share, 0.5);  // a hemisphere of lights is half of them at best
}

// The lookup finds a region whose centre is within ρ of the normal, and the nearest one for
// normals at the centres themselves.
TEST(AngularRegions, LookupStaysWithinTheRadius) {
  const AngularRegions regions(200, 32);
  const double cosRho = std::cos(regions.radiusDegrees() * 3.14159265358979323846 / 180);
  for (uint64_t n = 0; n < 20000; ++n) {
    const glm::dvec3 normal = randomDirection(n);
    EXPECT_GE(glm::dot(normal, regions.centre(regions.regionOf(normal))), cosRho) << n;
  }
  uint32_t ownRegion = 0;
  for (uint32_t r = 0; r < regions.size(); ++r)
    ownRegion += regions.regionOf(regions.centre(r)) == r;
  EXPECT_GT(ownRegion, 190u);  // texels straddling two cells may pick the neighbour
  EXPECT_THROW(AngularRegions(1, 32), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::envmap
