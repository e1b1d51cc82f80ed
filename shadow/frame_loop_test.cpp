// The per-frame loop on the bundled showroom: compose -> render -> observe with numbered
// frames, the controller's decisions, a camera background and a replaced product model.
#include "shadow/frame_loop.h"
#include "raster/closed_surface.h"
#include "tests/showroom_bundle.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace penumbra::shadow {
namespace {

// With graded transfers (fixed8_8 here; u8 alike) the loop renders with the probes and
// observes them; with linear accumulation (the default) it does neither.
TEST(FrameLoop, StepIsComposeRenderObserveWithNumberedFrames) {
  const SceneBundle& b = testing::showroomBundle();
  CompositorOptions graded;
  graded.accumulation = raster::Accumulation::kFixed8_8;
  FrameLoop loop(b, graded, {});
  FrameCompositor compositor(b, graded);
  raster::Renderer renderer(b.view, {});
  raster::FrameContent frame;
  CompositeStats stats;
  std::vector<uint8_t> rgba(b.background.size()), masks;
  for (uint32_t f = 1; f <= 3; ++f) {
    ProductPose pose = b.startPose;
    pose.x += 0.05f * float(f % 2);  // moves, then comes back: the feedback must carry over
    loop.step(pose, 8);
    compositor.compose(pose, 8, f, frame, stats);
    renderer.render(frame, rgba, compositor.probes(), masks, compositor.objectProbesFrom());
    compositor.observe(masks);
    EXPECT_EQ(loop.frameNumber, f);
    EXPECT_EQ(loop.rgba, rgba) << "frame " << f;
    EXPECT_EQ(loop.masks, masks) << "frame " << f;
    EXPECT_EQ(loop.stats.passes, stats.passes);
    EXPECT_GT(loop.frameNs, 0);
  }
  EXPECT_GT(loop.stats.gradedVertices, 0u) << "the third frame uses measured shares";

  FrameLoop linear(b, 256, {});
  EXPECT_FALSE(linear.compositor.measuresOcclusion());
  linear.step(b.startPose, 8);
  linear.step(b.startPose, 8);
  EXPECT_TRUE(linear.masks.empty());
  EXPECT_EQ(linear.stats.gradedVertices, 0u);
}

// The showroom's bunny has a fine proxy: the frame carries it placed as occluder 1 and its
// 16 most energetic passes draw it; the chair's proxy is its whole mesh, so it has none.
TEST(FrameLoop, TheMostEnergeticPassesDrawTheFineProxy) {
  const SceneBundle& b = testing::showroomBundle();
  ASSERT_GT(b.products[1].fineProxy.triangleCount(), b.products[1].proxy.triangleCount());
  ASSERT_TRUE(b.products[0].fineProxy.indices.empty());
  FrameCompositor compositor(b, {});
  raster::FrameContent frame;
  CompositeStats stats;
  const ProductPose bunny{1, 5.6f, 3.05f, 0.0f};
  compositor.compose(bunny, 50, 1, frame, stats);
  ASSERT_EQ(frame.occluders.size(), 2u);
  core::Mesh placed;
  placeMesh(b.products[1].fineProxy, bunny, placed);
  EXPECT_EQ(frame.occluders[1], placed);
  ASSERT_GT(frame.passes.size(), 16u);
  for (size_t k = 0; k < frame.passes.size(); ++k) {
    EXPECT_EQ(frame.passes[k].occluder, k < 16 ? 1u : 0u) << k;
  }
  CompositorOptions none;
  none.fineProxyPasses = 0;
  FrameCompositor coarse(b, none);
  coarse.compose(bunny, 50, 1, frame, stats);
  for (const raster::ShadowPass& pass : frame.passes) EXPECT_EQ(pass.occluder, 0u);
  compositor.compose({0, 3.0f, 2.4f, 0.0f}, 50, 2, frame, stats);
  EXPECT_EQ(frame.occluders.size(), 1u);
  for (const raster::ShadowPass& pass : frame.passes) EXPECT_EQ(pass.occluder, 0u);
}

// With a count per product (RenderSettings::productFineProxyPasses) each product's frames
// draw its own: the bunny's fine proxy in every pass, the teapot's in its 8 most energetic of
// 50 and the same share of 64 (ceil(64 * 8 / 50) = 11), whatever the shared count says.
TEST(FrameLoop, EachProductDrawsItsOwnFineProxyPasses) {
  const SceneBundle& b = testing::showroomBundle();
  // What precompute wrote from the scene file's `fine_proxy_passes` (the chair: the default).
  EXPECT_EQ(b.settings.productFineProxyPasses, (std::vector<uint32_t>{16, 32, 8}));
  CompositorOptions o;
  o.fineProxyPasses = 0;
  o.productFineProxyPasses = {16, 50, 8};
  FrameCompositor compositor(b, o);
  raster::FrameContent frame;
  CompositeStats stats;
  uint32_t tag = 0;
  for (const size_t passes : {50u, 64u}) {
    compositor.compose({1, 5.6f, 3.05f, 0.0f}, passes, ++tag, frame, stats);
    ASSERT_EQ(frame.passes.size(), passes);
    for (const raster::ShadowPass& pass : frame.passes) EXPECT_EQ(pass.occluder, 1u);
    compositor.compose({2, 5.6f, 3.05f, 0.0f}, passes, ++tag, frame, stats);
    ASSERT_EQ(frame.passes.size(), passes);
    const size_t fine = passes == 50 ? 8 : 11;
    for (size_t k = 0; k < frame.passes.size(); ++k) {
      EXPECT_EQ(frame.passes[k].occluder, k < fine ? 1u : 0u) << passes << " " << k;
    }
  }
  o.productFineProxyPasses = {16, 50};
  EXPECT_THROW(FrameCompositor(b, o), std::invalid_argument);
}

// The renderer counts the occluder triangles its passes draw (raster::FrameStats): at most
// the proxy's triangles per pass, more when the passes draw the bunny's fine proxy, and
// about half with closed proxies drawn front faces only. The same on every thread count.
TEST(FrameLoop, ShadowMapTrianglesCountWhatThePassesDraw) {
  const SceneBundle& b = testing::showroomBundle();
  const ProductPose bunny{1, 5.6f, 3.05f, 0.0f};
  const auto triangles = [&](std::vector<uint32_t> fine, bool cull, int threads) {
    CompositorOptions o;
    o.productFineProxyPasses = std::move(fine);
    o.cullClosedProxies = cull;
    FrameLoop loop(b, o, {simd::bestIsa(), threads, 32});
    loop.step(bunny, 50);
    EXPECT_EQ(loop.stats.passes, 50u);
    return loop.renderer.lastStats().shadowMapTriangles;
  };
  const uint64_t coarse = triangles({16, 0, 8}, false, 2);
  const uint64_t fine = triangles({16, 50, 8}, false, 2);
  EXPECT_GT(coarse, 0u);
  EXPECT_LE(coarse, 50 * b.products[1].proxy.triangleCount());
  EXPECT_GT(fine, 5 * coarse);
  EXPECT_LE(fine, 50 * b.products[1].fineProxy.triangleCount());
  const uint64_t culled = triangles({16, 50, 8}, true, 2);
  EXPECT_GT(culled, fine / 3);
  EXPECT_LT(culled, fine * 2 / 3);
  EXPECT_EQ(triangles({16, 50, 8}, true, 1), culled);
}

// The showroom's products are solid: their proxies are closed and wound outward (the Utah
// teapot's holes capped, scene/hole_capping.h), and culling their back faces draws the
// same frames, bit for bit.
TEST(FrameLoop, ClosedProxiesDrawTheSameFramesFrontFacesOnly) {
  const SceneBundle& b = testing::showroomBundle();
  for (const ProductModel& p : b.products) {
    EXPECT_TRUE(raster::isClosedOutwardSurface(p.proxy)) << p.name;
    if (!p.fineProxy.indices.empty()) {
      EXPECT_TRUE(raster::isClosedOutwardSurface(p.fineProxy)) << p.name;
    }
  }
  CompositorOptions all;
  all.cullClosedProxies = false;
  FrameLoop culled(b, CompositorOptions{}, {simd::bestIsa(), 2, 32});
  FrameLoop drawn(b, all, {simd::bestIsa(), 2, 32});
  for (const ProductPose& pose :
       {ProductPose{0, 5.45f, 2.9f, 90.0f}, ProductPose{1, 5.6f, 3.05f, 0},
        ProductPose{1, 3.0f, 2.4f, 120.0f}, ProductPose{2, 5.6f, 3.05f, 0},
        ProductPose{2, 2.6f, 2.0f, 90.0f}}) {
    culled.step(pose, 50);
    drawn.step(pose, 50);
    EXPECT_EQ(culled.rgba, drawn.rgba) << pose.product << " " << pose.x;
  }
}

TEST(FrameLoop, ControllerDecisionsSetTheMapSizeFromThatFrameOn) {
  FrameLoop loop(testing::showroomBundle(), 256, {});
  FrameRateController::Decision d;
  d.passes = 3;
  d.shadowMapSize = 128;
  loop.step(testing::showroomBundle().startPose, d);
  ASSERT_EQ(loop.frame.passes.size(), 3u);
  for (const raster::ShadowPass& p : loop.frame.passes) EXPECT_EQ(p.shadowMapSize, 128u);
  loop.step(testing::showroomBundle().startPose, 5);
  ASSERT_EQ(loop.frame.passes.size(), 5u);
  EXPECT_EQ(loop.frame.passes[4].shadowMapSize, 128u);
}

TEST(FrameLoop, ACameraFrameReplacesThePhotograph) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  const ProductPose away{0, 100.0f, 100.0f, 0.0f, 0.0f};  // nothing in view, no shadow
  loop.step(away, 10);
  EXPECT_EQ(loop.rgba, b.background);
  const std::vector<uint8_t> camera(b.background.size(), 77);
  loop.step(away, 10, camera);
  EXPECT_EQ(loop.rgba, camera);
  loop.step(away, 10);
  EXPECT_EQ(loop.rgba, b.background);
}

TEST(FrameLoop, AReplacedModelIsPlacedAfresh) {
  SceneBundle b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  loop.step(b.startPose, 4);
  const core::Mesh before = loop.frame.objects[0].mesh;
  for (core::Vec3& p : b.products[b.startPose.product].mesh.positions) p.y *= 0.5f;
  loop.step(b.startPose, 4);
  EXPECT_EQ(loop.frame.objects[0].mesh, before) << "not told: still the placed model";
  loop.productModelChanged(b.startPose.product);
  loop.step(b.startPose, 4);
  core::Mesh after;
  placeMesh(b.products[b.startPose.product].mesh, b.startPose, after);
  EXPECT_EQ(loop.frame.objects[0].mesh, after);
  EXPECT_NE(after, before);
}

}  // namespace
}  // namespace penumbra::shadow
