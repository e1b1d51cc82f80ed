// The pass list: one pass per cluster in the clusters' order, S in corner order over the
// receiver triangles that may be shadowed and have something to subtract, the product's
// own triangles, and no pass for a cluster whose light lies inside the product's sphere.
#include "shadow/pass_list.h"

#include <gtest/gtest.h>

#include "shadow/area_penumbra.h"
#include "shadow/light_frustum.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {
namespace {

// Two floor patches — one around the product, one 10 m away — and two lights: patch 2
// three metres above the product, patch 3 inside the product's bounding sphere.
struct Floor {
  Floor() {
    mesh.positions = {{-2, 0, -2}, {2, 0, -2}, {2, 0, 2},  {-2, 0, 2},
                      {10, 0, 0},  {12, 0, 0}, {12, 0, 2}, {10, 0, 2}};
    mesh.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    mesh.patches.resize(4);
    mesh.patches[1].firstTriangle = 2;
    bundle.patches.resize(4);
    bundle.patches[2].centre = {0, 3, 0};
    bundle.patches[3].centre = {0, 0.2f, 0};
    bundle.sets.sources = {2, 3};
    selection.clusters = {SourceCluster{0, 0, 0, 1, 0, 0}, SourceCluster{1, 1, 1, 1, 0, 0}};
    selection.sources = {0, 1};
    // The product: a tetrahedron in the box [-0.25, 0.25] x [0, 0.5] x [-0.25, 0.25].
    product.positions = {{-0.25f, 0, -0.25f}, {0.25f, 0, -0.25f}, {0, 0, 0.25f}, {0, 0.5f, 0}};
    product.indices = {0, 1, 2, 0, 1, 3, 1, 2, 3};
    bounds = {{-0.25, 0, -0.25}, {0.25, 0.5, 0.25}};
    // Mesh vertex v -> receiver vertex v, slot 7 - v. Vertex 7 receives nothing.
    receiverVertexOf = {0, 1, 2, 3, 4, 5, 6, kNoIndex};
    vertexSlot = {7, 6, 5, 4, 3, 2, 1};
    receiverS.resize(8 * 2);
    for (uint8_t slot = 0; slot < 8; ++slot) {
      receiverS[2 * slot] = {uint8_t(10 + slot), 0, 0};
      receiverS[2 * slot + 1] = {0, uint8_t(20 + slot), 0};
    }
    receiverS[2 * vertexSlot[0]] = {};  // triangle 1 (0, 2, 3): vertex 0 without S...
    receiverS[2 * vertexSlot[2]] = {};
    receiverS[2 * vertexSlot[3]] = {};  // ...and its other corners too: nothing to subtract
    productS.resize(4 * 2);
    for (uint8_t v = 0; v < 4; ++v) productS[2 * v] = {0, 0, uint16_t(30 + v)};
    productS[2 * 3] = {};  // triangles 1 and 2 keep corner 0 or 1 or 2 lit
  }
  VertexS s() const { return {receiverVertexOf, vertexSlot, receiverS, productS, 2}; }

  SceneBundle bundle;
  scene::PatchMesh mesh;
  ClusterSelection selection;
  core::Mesh product;
  scene::Aabb bounds;
  std::vector<uint32_t> receiverVertexOf, vertexSlot;
  std::vector<core::Rgb16> receiverS, productS;
};

const scene::Aabb kRoom{{-2, 0, -2}, {12, 3, 2}};

// Area penumbrae: each pass carries its light's scale and blocker depth (shadow/area_penumbra.h)
// when asked, with 2x2 PCF and a map of at most 512 texels; otherwise, and on reused passes,
// both are 0.
TEST(PassList, AreaPenumbraeCarryEachLightsScale) {
  Floor f;
  f.bundle.patches[3].centre = {0, 3, 1};
  f.bundle.patches[2].area = 0.04f;  // 0.2 m patches
  f.bundle.patches[3].area = 0.04f;
  f.bundle.transfers.sourceAverage = {1.0f, 0.5f};
  PassList list(f.bundle, f.mesh, kRoom);
  PassListOptions options;
  options.areaPenumbrae = true;
  std::vector<raster::ShadowPass> passes;
  list.build(options, f.selection, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes);
  ASSERT_EQ(passes.size(), 2u);
  const double far = 2.0 * glm::length(kRoom.size()) + 1.0;
  for (size_t k = 0; k < 2; ++k) {
    const glm::dvec3 light(f.bundle.patches[f.bundle.sets.sources[k]].centre);
    const auto frustum = fitLightFrustum(light, f.bounds, far);
    const glm::dvec3 axis = glm::normalize(frustum->sphereCentre - light);
    SourceCluster one = f.selection.clusters[k];
    EXPECT_EQ(passes[k].penumbraScale,
              static_cast<float>(penumbraScale(
                  *frustum, clusterHalfWidth(f.bundle, one, f.selection.sources, light, axis),
                  options.shadowMapSize)));
    EXPECT_GT(passes[k].penumbraScale, 0.0f);
  }
  // Off, without 2x2 PCF, or with a larger map: hard passes, into the same (reused) passes.
  PassListOptions binary = options, large = options;
  binary.pcf2x2 = false;
  large.shadowMapSize = 1024;
  for (const PassListOptions& hard : {PassListOptions{}, binary, large}) {
    list.build(hard, f.selection, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes);
    for (const raster::ShadowPass& pass : passes) {
      EXPECT_EQ(pass.penumbraScale, 0.0f);
    }
  }
}

TEST(PassList, OnePassPerClusterWithSInCornerOrder) {
  Floor f;
  f.receiverS[2 * f.vertexSlot[2]] = {1, 0, 0};  // triangle 1 has S again
  PassList list(f.bundle, f.mesh, kRoom);
  PassListOptions options;
  options.shadowMapSize = 128;
  options.depthBias = 0.005f;
  options.pcf2x2 = false;
  options.objectDepthBias = 0.02f;
  f.bundle.patches[3].centre = {0, 3, 1};     // both lights outside the product
  std::vector<raster::ShadowPass> passes(5);  // reused: whatever was there goes
  const uint32_t skipped = list.build(options, f.selection, std::vector<uint32_t>{0}, f.product,
                                      f.bounds, f.s(), passes);
  EXPECT_EQ(skipped, 0u);
  ASSERT_EQ(passes.size(), 2u);
  EXPECT_EQ(std::vector<uint32_t>(list.passCluster().begin(), list.passCluster().end()),
            (std::vector<uint32_t>{0, 1}));
  const double far = 2.0 * glm::length(kRoom.size()) + 1.0;
  for (size_t k = 0; k < 2; ++k) {
    const raster::ShadowPass& pass = passes[k];
    const uint32_t light = f.bundle.sets.sources[k];
    EXPECT_EQ(
        pass.lightViewProj,
        fitLightFrustum(glm::dvec3(f.bundle.patches[light].centre), f.bounds, far)->rasterViewProj);
    EXPECT_EQ(pass.shadowMapSize, 128u);
    EXPECT_EQ(pass.depthBias, 0.005f);
    EXPECT_FALSE(pass.pcf2x2);
    EXPECT_EQ(pass.occluder, 0u);
    EXPECT_EQ(pass.objectDepthBias, 0.02f);
    ASSERT_EQ(pass.receiverTriangles, (std::vector<uint32_t>{0, 1}));
    ASSERT_EQ(pass.receiverS.size(), 6u);
    const uint32_t corners[6] = {0, 1, 2, 0, 2, 3};  // the triangles' vertices, in order
    for (size_t c = 0; c < 6; ++c) {
      EXPECT_EQ(pass.receiverS[c], f.receiverS[2 * f.vertexSlot[corners[c]] + k]) << c;
    }
  }
  // Self-shadowing: cluster 0's S on the product's triangles; cluster 1 has none there.
  EXPECT_EQ(passes[0].objectTriangles, (std::vector<uint32_t>{0, 1, 2}));
  const std::vector<core::Rgb16> objectS{f.productS[0], f.productS[2], f.productS[4],
                                         f.productS[0], f.productS[2], f.productS[6],
                                         f.productS[2], f.productS[4], f.productS[6]};
  EXPECT_EQ(passes[0].objectS, objectS);
  EXPECT_TRUE(passes[1].objectTriangles.empty());
  EXPECT_TRUE(passes[1].objectS.empty());
}

TEST(PassList, TrianglesWithoutSAndOutsideTheFrustumAreLeftOut) {
  Floor f;
  f.bundle.patches[3].centre = {0, 3, 1};
  PassList list(f.bundle, f.mesh, kRoom);
  std::vector<raster::ShadowPass> passes;
  const std::vector<uint32_t> both{0, 1};
  list.build({}, f.selection, both, f.product, f.bounds, f.s(), passes);
  ASSERT_EQ(passes.size(), 2u);
  // Triangle 1 has no S for cluster 0; the far patch (triangles 2, 3) is outside the
  // light's frustum. Cluster 1 has S on triangle 1 (its corners' second entries).
  EXPECT_EQ(passes[0].receiverTriangles, (std::vector<uint32_t>{0}));
  EXPECT_EQ(passes[1].receiverTriangles, (std::vector<uint32_t>{0, 1}));
  // Without culling, the far patch gets its S too (vertex 7 has none: zero at that corner).
  PassListOptions all;
  all.cullReceivers = false;
  list.build(all, f.selection, both, f.product, f.bounds, f.s(), passes);
  EXPECT_EQ(passes[0].receiverTriangles, (std::vector<uint32_t>{0, 2, 3}));
  ASSERT_EQ(passes[0].receiverS.size(), 9u);
  EXPECT_EQ(passes[0].receiverS[8], core::Rgb16{});
  EXPECT_EQ(passes[0].receiverS[7], f.receiverS[2 * f.vertexSlot[6]]);
}

TEST(PassList, ALightInsideTheProductsSphereGetsNoPass) {
  const Floor f;
  PassList list(f.bundle, f.mesh, kRoom);
  std::vector<raster::ShadowPass> passes;
  const uint32_t skipped =
      list.build({}, f.selection, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes);
  EXPECT_EQ(skipped, 1u);
  ASSERT_EQ(passes.size(), 1u);
  EXPECT_EQ(std::vector<uint32_t>(list.passCluster().begin(), list.passCluster().end()),
            (std::vector<uint32_t>{0}));
  // Without self-shadowing S, no product triangle receives.
  Floor noSelf;
  noSelf.productS.clear();
  list.build({}, noSelf.selection, std::vector<uint32_t>{0}, noSelf.product, noSelf.bounds,
             noSelf.s(), passes);
  EXPECT_TRUE(passes[0].objectTriangles.empty());
}

// The first fineProxyPasses passes built (not clusters: a cluster without a pass does not
// count) draw occluder 1, the product's fine proxy; the rest its proxy.
TEST(PassList, TheFirstPassesDrawTheFineProxy) {
  Floor f;
  f.bundle.patches[3].centre = {0, 3, 1};
  PassList list(f.bundle, f.mesh, kRoom);
  PassListOptions options;
  std::vector<raster::ShadowPass> passes;
  for (uint32_t fine : {0u, 1u, 2u, 5u}) {
    options.fineProxyPasses = fine;
    list.build(options, f.selection, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes);
    ASSERT_EQ(passes.size(), 2u);
    for (uint32_t k = 0; k < 2; ++k) EXPECT_EQ(passes[k].occluder, k < fine ? 1u : 0u) << fine;
  }
  // Cluster 0's light inside the product's sphere: cluster 1's pass is the first.
  f.bundle.patches[2].centre = {0, 0.2f, 0};
  options.fineProxyPasses = 1;
  EXPECT_EQ(list.build(options, f.selection, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(),
                       passes),
            1u);
  ASSERT_EQ(passes.size(), 1u);
  EXPECT_EQ(list.passCluster()[0], 1u);
  EXPECT_EQ(passes[0].occluder, 1u);
  EXPECT_FALSE(passes[0].cullBackFaces);
  // A closed occluder's passes cull back faces, per occluder.
  f.bundle.patches[2].centre = {0, 3, 0};
  options.fineProxyPasses = 1;
  for (const std::array<bool, 2> closed : {std::array{true, false}, std::array{false, true}}) {
    options.closedOccluders = closed;
    list.build(options, f.selection, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes);
    ASSERT_EQ(passes.size(), 2u);
    EXPECT_EQ(passes[0].cullBackFaces, closed[1]);  // draws occluder 1
    EXPECT_EQ(passes[1].cullBackFaces, closed[0]);
  }
}

// Beyond 50 passes the fine proxy keeps its share of them: 16 of 50, 27 of 82 (16 * 82 / 50 =
// 26.24, rounded up), all of them when the count asks for more than there are.
TEST(PassList, TheFineProxysShareHoldsAboveFiftyPasses) {
  EXPECT_EQ(fineProxyPassesFor(16, 10), 16u);
  EXPECT_EQ(fineProxyPassesFor(16, 50), 16u);
  EXPECT_EQ(fineProxyPassesFor(16, 51), 17u);
  EXPECT_EQ(fineProxyPassesFor(16, 82), 27u);
  EXPECT_EQ(fineProxyPassesFor(16, 257), 83u);
  EXPECT_EQ(fineProxyPassesFor(0, 200), 0u);
  EXPECT_EQ(fineProxyPassesFor(50, 60), 60u);
  EXPECT_EQ(fineProxyPassesFor(200, 100), 100u);
}

// A cluster's map is cast from its sources' centroid weighted by their average transfers;
// one source casts from its patch centre exactly; a centroid inside the product's sphere
// falls back to the representative patch.
TEST(PassList, AClusterCastsFromItsEnergyWeightedCentroid) {
  Floor f;
  f.bundle.transfers.sourceAverage = {3.0f, 1.0f};
  PassList list(f.bundle, f.mesh, kRoom);
  // Patch 2 at (0, 3, 0) weighs 3, patch 3 at (0, 0.2, 0) weighs 1: (0, 2.3, 0).
  const SourceCluster both{0, 0, 0, 2, 0, 0};
  const glm::dvec3 centroid = list.clusterCentroid(both, f.selection.sources);
  EXPECT_NEAR(centroid.x, 0.0, 1e-12);
  EXPECT_NEAR(centroid.y, (3.0 * 3.0 + 1.0 * double(0.2f)) / 4.0, 1e-12);
  EXPECT_NEAR(centroid.z, 0.0, 1e-12);
  EXPECT_EQ(list.clusterCentroid(f.selection.clusters[1], f.selection.sources),
            glm::dvec3(f.bundle.patches[3].centre));
  ClusterSelection one = f.selection;
  one.clusters = {both};
  std::vector<raster::ShadowPass> passes;
  ASSERT_EQ(list.build({}, one, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes), 0u);
  ASSERT_EQ(passes.size(), 1u);
  const double far = 2.0 * glm::length(kRoom.size()) + 1.0;
  EXPECT_EQ(passes[0].lightViewProj, fitLightFrustum(centroid, f.bounds, far)->rasterViewProj);
  // Weights 1 and 30 put the centroid at y = 0.29, inside the product's sphere: the map is
  // cast from the representative, patch 2, and the cluster keeps its pass.
  f.bundle.transfers.sourceAverage = {1.0f, 30.0f};
  ASSERT_FALSE(fitLightFrustum(list.clusterCentroid(both, f.selection.sources), f.bounds, far));
  ASSERT_EQ(list.build({}, one, std::vector<uint32_t>{0}, f.product, f.bounds, f.s(), passes), 0u);
  ASSERT_EQ(passes.size(), 1u);
  EXPECT_EQ(passes[0].lightViewProj,
            fitLightFrustum(glm::dvec3(0, 3, 0), f.bounds, far)->rasterViewProj);
}

}  // namespace
}  // namespace penumbra::shadow
