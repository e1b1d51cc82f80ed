#include "shadow/area_penumbra.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scene/camera.h"

namespace penumbra::shadow {
namespace {

using glm::dvec3;

// The header's K against the geometry it comes from: a blocker edge at one depth, a
// receiver plane at another, a light moved by its half-width ρ across the axis. The edge's
// shadow moves by ρ (zr - zb) / zb on the receiver; projected into the light's map that is
// K (dr - db) texels, with the window depths d of the two points.
TEST(AreaPenumbra, ScaleIsTheShadowShiftOfALightMovedByItsHalfWidth) {
  const scene::Aabb box{dvec3(-0.2, 0.8, -0.2), dvec3(0.2, 1.2, 0.2)};
  const dvec3 light(0.3, 3.5, 0.1);
  const auto frustum = fitLightFrustum(light, box, 12.0);
  ASSERT_TRUE(frustum.has_value());
  const uint32_t size = 256;
  const double rho = 0.1;
  const double k = penumbraScale(*frustum, rho, size);
  // Along the axis: a blocker point and a receiver point behind it.
  const dvec3 axis = glm::normalize(frustum->sphereCentre - light);
  const double zb = glm::length(frustum->sphereCentre - light), zr = zb + 1.7;
  auto windowDepth = [&](double z) {
    const glm::dvec4 c = frustum->viewProj * glm::dvec4(light + z * axis, 1.0);
    return c.z / c.w * 0.5 + 0.5;
  };
  const double shiftTexels = k * (windowDepth(zr) - windowDepth(zb));
  // The same shift measured in the map: the receiver point's shadow moves by
  // ρ (zr - zb) / zb across the axis; its texel coordinate in the (unmoved) map changes by
  // that over the texel's width at depth zr.
  const double texelAtReceiver = 2.0 * frustum->tanHalfFovY * zr / size;
  EXPECT_NEAR(shiftTexels, rho * (zr - zb) / zb / texelAtReceiver, 1e-6 * shiftTexels);
  // No light, no penumbra; an orthographic (distant) light has none of this kind.
  EXPECT_EQ(penumbraScale(*frustum, 0.0, size), 0.0);
  LightFrustum ortho = *frustum;
  ortho.orthographic = true;
  EXPECT_EQ(penumbraScale(ortho, rho, size), 0.0);
}

// One square patch seen along its normal: the box light of its own half-width, a / 2. Two
// equal patches side by side across the axis: the spread of both, sqrt(3 (a²/12 + s²/4))
// for centres s apart; the weights follow the sources' transfers.
TEST(AreaPenumbra, ClusterHalfWidthIsTheBoxWithTheSourcesSpread) {
  SceneBundle bundle;
  const double a = 0.2;
  PatchRecord patch{};
  patch.area = float(a * a);
  patch.centre = glm::vec3(0, 3, 0);
  bundle.patches = {patch, patch};
  bundle.patches[1].centre = glm::vec3(0.6f, 3, 0);
  bundle.sets.sources = {0, 1};
  bundle.transfers.sourceAverage = {1.0f, 1.0f};
  const std::vector<uint32_t> sources = {0, 1};
  const dvec3 down(0, -1, 0);
  SourceCluster one;
  one.firstSource = 0;
  one.sourceCount = 1;
  EXPECT_NEAR(clusterHalfWidth(bundle, one, sources, dvec3(0, 3, 0), down), a / 2, 1e-7);
  SourceCluster both;
  both.firstSource = 0;
  both.sourceCount = 2;
  const dvec3 centroid(0.3, 3, 0);
  const double expected = std::sqrt(3.0 * (a * a / 12 + 0.5 * 0.3 * 0.3));
  EXPECT_NEAR(clusterHalfWidth(bundle, both, sources, centroid, down), expected, 1e-6);
  // Along the axis the offset does not count: the same pair seen edge-on.
  EXPECT_NEAR(clusterHalfWidth(bundle, both, sources, centroid, dvec3(1, 0, 0)), a / 2, 1e-6);
  // The second source nearly dark: the first one's own width.
  bundle.transfers.sourceAverage = {1.0f, 0.0f};
  EXPECT_NEAR(clusterHalfWidth(bundle, both, sources, dvec3(0, 3, 0), down), a / 2, 1e-4);
}

}  // namespace
}  // namespace penumbra::shadow
