#include "envmap/light_clustering.h"

#include <gtest/gtest.h>

#include <cmath>

#include "envmap/envmap_sampling.h"
#include "envmap/envmap_test_util.h"
#include "envmap/light_filter.h"

namespace penumbra::envmap {
namespace {

using testutil::angleDegrees;

void expectSamePower(const glm::dvec3& a, const glm::dvec3& b) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-12 * b[c]) << "channel " << c;
}

// Havran 2005 §4.3: e = c_f · arcsin √(2/Q); Q = 72 (the paper's shadow-map count) gives
// 1.85 × 9.594° = 17.75°.
TEST(LightClustering, RadiusFollowsThePaper) {
  for (uint32_t q : {3u, 10u, 72u, 300u}) {
    const double expected = 1.85 * std::asin(std::sqrt(2.0 / q)) * 180 / 3.14159265358979323846;
    EXPECT_NEAR(clusterRadiusDegrees(q), expected, 1e-9) << "Q = " << q;
  }
  EXPECT_NEAR(clusterRadiusDegrees(72), 17.75, 0.01);
  EXPECT_NEAR(clusterRadiusDegrees(1, 1.0), 90.0, 1e-9);
  EXPECT_THROW(clusterRadiusDegrees(0), std::invalid_argument);
  EXPECT_THROW(clusterLights({}, 72, 0.0), std::invalid_argument);
}

// 300 filtered lights of a window map → at most 72 clusters; each light within e of its
// cluster's seed (no cluster was merged: fewer than Q formed); power conserved; ids are the
// seeds' ids, increasing.
TEST(LightClustering, ConservesEnergyWithinTheRadius) {
  const EnvmapDistribution distribution(testutil::windowMap());
  TemporalLightFilter filter;
  const LightSet lights = filter.push(distribution.sample(SamplePattern(300), 300));
  const LightClusters clusters = clusterLights(lights, 72);
  ASSERT_LT(clusters.lights.size(), 72u);
  EXPECT_GT(clusters.lights.size(), 10u);
  expectSamePower(totalPower(clusters.lights), totalPower(lights));
  const double e = clusterRadiusDegrees(72);
  for (size_t i = 0; i < lights.size(); ++i) {
    const DirectionalLight& cluster = clusters.lights[clusters.clusterOf[i]];
    EXPECT_LE(angleDegrees(lights[cluster.id - 1].direction, lights[i].direction), e) << i;
    EXPECT_LE(angleDegrees(cluster.direction, lights[i].direction), 2 * e) << i;
  }
  for (size_t c = 1; c < clusters.lights.size(); ++c)
    EXPECT_LT(clusters.lights[c - 1].id, clusters.lights[c].id);
  // The window (2.5% of the pixels, about 60% of the luminance power) ends up in few
  // clusters: the brightest cluster holds more than 4 equal shares.
  double brightest = 0;
  for (const DirectionalLight& c : clusters.lights) brightest = std::max(brightest, c.power.r);
  EXPECT_GT(brightest, 4 * totalPower(lights).r / double(clusters.lights.size()));
}

// Lights spread evenly over the hemisphere: with c_f = 1.85 the discs are wide enough that the
// greedy pass stays under Q (measured: Q = 4, 16, 72 give 3, 10, 39 clusters); with c_f = 1 it
// makes more than Q and the extra clusters are merged: exactly Q remain. Energy is conserved
// either way and every direction is a unit vector.
TEST(LightClustering, NeverMoreThanQClusters) {
  const EnvmapDistribution distribution(testutil::uniformMap({1, 1, 1}));
  const LightSet lights = distribution.sample(SamplePattern(300), 300);
  for (double correction : {1.85, 1.0}) {
    for (uint32_t q : {1u, 4u, 16u, 72u}) {
      const LightClusters clusters = clusterLights(lights, q, correction);
      EXPECT_LE(clusters.lights.size(), q);
      if (correction == 1.0) {
        EXPECT_EQ(clusters.lights.size(), q);
      } else if (q == 72) {
        EXPECT_GT(clusters.lights.size(), 20u);
      }
      expectSamePower(totalPower(clusters.lights), totalPower(lights));
      for (const DirectionalLight& c : clusters.lights)
        EXPECT_NEAR(glm::length(c.direction), 1.0, 1e-12);
    }
  }
  EXPECT_EQ(clusterLights(lights, 1).lights[0].id, 1u);
  EXPECT_TRUE(clusterLights({}, 8).lights.empty());
}

}  // namespace
}  // namespace penumbra::envmap
