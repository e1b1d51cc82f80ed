#include "shadow/cluster_map_size.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "shadow/frame_loop.h"
#include "tests/camera_view.h"
#include "tests/showroom_bundle.h"

namespace penumbra::shadow {
namespace {

// A 640x480 camera 4 m above the floor looking straight down (60° vertical field of view):
// every floor point at a known scale, f / 4 pixels per metre.
raster::StaticView downView() {
  return testing::cameraView(glm::dvec3(0, 4, 0), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, -1));
}
const double kFocal = testing::kFocalPx;
const scene::Aabb kRoom{glm::dvec3(-5, 0, -5), glm::dvec3(5, 5, 5)};
const scene::Aabb kProduct{glm::dvec3(-0.3, 0.7, -0.3), glm::dvec3(0.3, 1.3, 0.3)};

// A light 3 m above the floor, straight over the product: the window of half-angle α lands
// on the floor as a square of half-width 3 tan α, seen at f / 4 pixels per metre.
TEST(ClusterMapSize, AShadowStraightBelowIsTheWindowOnTheFloor) {
  const glm::dvec3 light(0, 3, 0);
  const auto frustum = fitLightFrustum(light, kProduct, 20.0);
  ASSERT_TRUE(frustum);
  const double expected = 2.0 * 3.0 * frustum->tanHalfFovY * kFocal / 4.0;
  EXPECT_NEAR(shadowFootprintPx(downView(), *frustum, light, kRoom), expected, 1e-3 * expected);
}

// A light off to the side at angle θ from the vertical: the window's edges along the tilt
// reach the floor at 3 tan(θ ± α) from the light's foot: at θ = 45° at least 1 / cos θ = 1.41
// times the shadow's width across the tilt (the window's width where the axis meets the floor).
TEST(ClusterMapSize, AnObliqueLightStretchesTheShadowAlongItsTilt) {
  const glm::dvec3 light(2, 3, 0);
  const auto frustum = fitLightFrustum(light, kProduct, 20.0);
  ASSERT_TRUE(frustum);
  const double theta = std::atan2(2.0, 2.0);  // towards the sphere's centre (0, 1, 0)
  const double alpha = std::atan(frustum->tanHalfFovY);
  const double along = 3.0 * (std::tan(theta + alpha) - std::tan(theta - alpha));
  const double px = shadowFootprintPx(downView(), *frustum, light, kRoom);
  EXPECT_NEAR(px, along * kFocal / 4.0, 1e-3 * px);
  const double across = 2.0 * frustum->tanHalfFovY * (3.0 / std::cos(theta)) * kFocal / 4.0;
  EXPECT_GT(px, 1.41 * across);
}

// No bounded footprint: behind the camera, or grazing a face. Those clusters keep the
// frame's map.
TEST(ClusterMapSize, AFootprintTheCameraCannotMeasureIsInfinite) {
  const auto frustum = fitLightFrustum(glm::dvec3(0, 3, 0), kProduct, 20.0);
  ASSERT_TRUE(frustum);
  const raster::StaticView up =
      testing::cameraView(glm::dvec3(0, 4, 0), glm::dvec3(0, 8, 0), glm::dvec3(0, 0, -1));
  EXPECT_TRUE(std::isinf(shadowFootprintPx(up, *frustum, glm::dvec3(0, 3, 0), kRoom)));
  // A light 1 cm above the floor, 4.9 m from a flat product: the axis dips to meet the floor
  // 9.8 m on, and the window's upper edge heads up, away from it.
  const glm::dvec3 low(4.9, 0.01, 0.0);
  const auto grazing = fitLightFrustum(
      low, scene::Aabb{glm::dvec3(-0.3, 0, -0.3), glm::dvec3(0.3, 0.01, 0.3)}, 20.0);
  ASSERT_TRUE(grazing);
  EXPECT_TRUE(std::isinf(shadowFootprintPx(downView(), *grazing, low, kRoom)));
  EXPECT_EQ(clusterMapSize(std::numeric_limits<double>::infinity(), 1.0, 256), 256u);
  EXPECT_EQ(clusterMapSize(std::nan(""), 1.0, 256), 256u);
}

TEST(ClusterMapSize, TexelsPerPixelRoundedUpToSixteenWithinTheFramesMap) {
  EXPECT_EQ(clusterMapSize(100.0, 2.0, 256), 208u);  // 200 -> 208
  EXPECT_EQ(clusterMapSize(96.0, 1.0, 256), 96u);    // exact
  EXPECT_EQ(clusterMapSize(10.0, 1.0, 256), kMinClusterMapSize);
  EXPECT_EQ(clusterMapSize(1000.0, 1.0, 256), 256u);
  EXPECT_EQ(clusterMapSize(10.0, 1.0, 16), 16u);     // a frame map below the floor stays
  EXPECT_EQ(clusterMapSize(100.0, 0.0, 256), 256u);  // off
}

// The showroom's start pose with 24 passes: each pass's map is its cluster's size, never more
// than the frame's, more texels per pixel never give a smaller map, the area penumbra's box is
// the same width in metres (its scale in texels follows the map), and the renderer counts the
// texels the board is charged for.
TEST(ClusterMapSize, ThePassesOfAShowroomFrameTakeTheirClustersMaps) {
  const SceneBundle& b = testing::showroomBundle();
  const auto passesWith = [&](double texelsPerPixel) {
    CompositorOptions o;
    o.texelsPerShadowPixel = texelsPerPixel;
    FrameLoop loop(b, o, {});
    loop.step(b.startPose, 24);
    uint64_t texels = 0;
    for (const raster::ShadowPass& p : loop.frame.passes) {
      texels += uint64_t{p.shadowMapSize} * p.shadowMapSize;
    }
    EXPECT_EQ(loop.renderer.lastStats().shadowMapTexels, texels) << texelsPerPixel;
    return loop.frame.passes;
  };
  const auto whole = passesWith(0), one = passesWith(1.0), two = passesWith(2.0);
  ASSERT_EQ(whole.size(), 24u);
  ASSERT_EQ(one.size(), whole.size());
  ASSERT_EQ(two.size(), whole.size());
  std::set<uint32_t> sizes;
  for (size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(whole[i].shadowMapSize, 256u);
    EXPECT_EQ(one[i].lightViewProj, whole[i].lightViewProj) << "the same clusters, pass " << i;
    EXPECT_LE(one[i].shadowMapSize, 256u);
    EXPECT_EQ(one[i].shadowMapSize % 16, 0u);
    EXPECT_GE(one[i].shadowMapSize, kMinClusterMapSize);
    EXPECT_LE(one[i].shadowMapSize, two[i].shadowMapSize) << "pass " << i;
    sizes.insert(one[i].shadowMapSize);
    if (whole[i].penumbraScale > 0 && one[i].penumbraScale > 0) {
      const double perTexel = double(whole[i].penumbraScale) / 256.0;
      EXPECT_NEAR(double(one[i].penumbraScale) / one[i].shadowMapSize, perTexel, 1e-6 * perTexel)
          << "pass " << i;
    }
  }
  EXPECT_GE(sizes.size(), 2u) << "the clusters' shadows differ on screen";
  EXPECT_LT(*sizes.begin(), 256u);
}

}  // namespace
}  // namespace penumbra::shadow
