// Frame-level behaviour of the Renderer: what must and must not change the pixels.
#include "raster/renderer.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <tuple>

#include "raster/closed_surface.h"
#include "simd/targets.h"
#include "tests/test_scenes.h"

namespace penumbra {
namespace {

using raster::RenderOptions;

TEST(Renderer, ObjectOutsideEveryShadowLeavesTheBackground) {
  testing::TestSceneOptions o;
  o.objectVisible = false;
  o.objectOffsetX = 40.0f;  // far outside the room: every light looks away from the floor
  const raster::FrameTrace t = testing::makeTestScene(o);
  EXPECT_EQ(raster::renderTrace(t, {simd::bestIsa(), 2, 32}), t.frame.background);
}

TEST(Renderer, NoPassesDrawsOnlyTheObject) {
  testing::TestSceneOptions o;
  o.passes = 0;
  const raster::FrameTrace t = testing::makeTestScene(o);
  const auto out = raster::renderTrace(t, {simd::Isa::kScalar, 1, 32});
  size_t changed = 0;
  for (size_t i = 0; i < out.size(); ++i) changed += out[i] != t.frame.background[i];
  EXPECT_GT(changed, 0u);
  raster::FrameTrace hidden = t;
  hidden.frame.objects.clear();
  EXPECT_EQ(raster::renderTrace(hidden, {simd::Isa::kScalar, 1, 32}), t.frame.background);
}

TEST(Renderer, ShadowsOnlyDarken) {
  const raster::FrameTrace t = testing::makeTestScene({});
  raster::FrameTrace noShadow = t;
  noShadow.frame.passes.clear();
  const auto lit = raster::renderTrace(noShadow, {simd::bestIsa(), 1, 32});
  const auto shadowed = raster::renderTrace(t, {simd::bestIsa(), 1, 32});
  size_t darker = 0;
  for (size_t i = 0; i < lit.size(); ++i) {
    ASSERT_LE(shadowed[i], lit[i]) << "byte " << i;
    darker += shadowed[i] < lit[i];
  }
  EXPECT_GT(darker, 100u) << "the occluder must cast a visible shadow";
}

TEST(Renderer, SelfShadowingDarkensOnlyTheObject) {
  const raster::FrameTrace t = testing::makeTestScene({});
  raster::FrameTrace roomOnly = t;
  for (auto& pass : roomOnly.frame.passes) {
    pass.objectTriangles.clear();
    pass.objectS.clear();
  }
  const auto with = raster::renderTrace(t, {simd::bestIsa(), 2, 32});
  const auto without = raster::renderTrace(roomOnly, {simd::bestIsa(), 2, 32});
  raster::FrameTrace noPasses = t;
  noPasses.frame.passes.clear();
  const auto objectOnly = raster::renderTrace(noPasses, {simd::Isa::kScalar, 1, 32});
  auto isObjectPixel = [&](size_t px) {
    for (size_t c = 0; c < 4; ++c) {
      if (objectOnly[4 * px + c] != t.frame.background[4 * px + c]) return true;
    }
    return false;
  };
  size_t darker = 0;
  for (size_t i = 0; i < with.size(); ++i) {
    ASSERT_LE(with[i], without[i]) << "byte " << i;
    if (with[i] == without[i]) continue;
    ++darker;
    ASSERT_TRUE(isObjectPixel(i / 4)) << "self-shadowing touched a room pixel, byte " << i;
  }
  EXPECT_GT(darker, 50u);
}

TEST(Renderer, MovingTheObjectMovesTheShadow) {
  testing::TestSceneOptions o;
  const auto a = raster::renderTrace(testing::makeTestScene(o), {simd::bestIsa(), 2, 16});
  o.objectOffsetX = 0.5f;
  const auto b = raster::renderTrace(testing::makeTestScene(o), {simd::bestIsa(), 2, 16});
  EXPECT_NE(a, b);
}

TEST(Renderer, RendersManyFramesIdentically) {
  const raster::FrameTrace t = testing::makeTestScene({});
  raster::Renderer r(t.view, {simd::bestIsa(), 3, 32});
  std::vector<uint8_t> first(t.frame.background.size()), again(first.size());
  r.render(t.frame, first);
  for (int i = 0; i < 3; ++i) {
    r.render(t.frame, again);
    ASSERT_EQ(first, again);
  }
  EXPECT_GT(r.lastStats().passPixels, 0u);
  EXPECT_GT(r.lastStats().shadowMapPixels, 0u);
}

// Fixed-point accumulation (spec §8) keeps each pixel's S and S·M to 1/256 level and rounds
// the sum once; u8 rounds S and S·M/255 per pass, so the two differ by at most half a level
// per pass, plus one — wherever S is interpolated between corners or M is fractional.
TEST(Renderer, FixedPointAccumulationDiffersOnlyInThePerPassRounding) {
  for (bool pcf : {false, true}) {
    testing::TestSceneOptions o;
    o.pcf2x2 = pcf;
    o.passes = 12;
    const raster::FrameTrace u8 = testing::makeTestScene(o);
    raster::FrameTrace fixed = u8;
    fixed.frame.accumulation = raster::Accumulation::kFixed8_8;
    const auto a = raster::renderTrace(u8, {simd::bestIsa(), 2, 32});
    const auto b = raster::renderTrace(fixed, {simd::bestIsa(), 2, 32});
    size_t differ = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      ASSERT_LE(std::abs(int(a[i]) - int(b[i])), o.passes / 2 + 1) << "byte " << i;
      differ += a[i] != b[i];
    }
    EXPECT_GT(differ, 0u) << "interpolated S must round differently";
  }
}

// The test scene's box with corners shared by index: a closed surface.
core::Mesh welded(const core::Mesh& m) {
  core::Mesh out;
  std::map<std::tuple<float, float, float>, uint32_t> index;
  for (const uint32_t i : m.indices) {
    const core::Vec3& p = m.positions[i];
    const auto [it, added] =
        index.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(out.positions.size()));
    if (added) out.positions.push_back(p);
    out.indices.push_back(it->second);
  }
  return out;
}

// Culling back faces (ShadowPass::cullBackFaces) draws the same frame for a closed occluder
// wound counter-clockwise from outside, room and self-shadowing receivers alike, on every
// target; for an open one (the box without its top, lit from above) it loses shadow.
TEST(Renderer, CullingAClosedOccludersBackFacesDrawsTheSameFrame) {
  testing::TestSceneOptions o;
  o.pcf2x2 = true;
  raster::FrameTrace all = testing::makeTestScene(o);
  all.frame.occluders[0] = welded(all.frame.occluders[0]);
  ASSERT_TRUE(raster::isClosedOutwardSurface(all.frame.occluders[0]));
  raster::FrameTrace culled = all;
  for (raster::ShadowPass& pass : culled.frame.passes) pass.cullBackFaces = true;
  const auto expected = raster::renderTrace(all, {simd::Isa::kScalar, 1, 32});
  for (const simd::Isa isa : simd::supportedIsas()) {
    for (const int threads : {1, 2}) {
      EXPECT_EQ(raster::renderTrace(culled, {isa, threads, 32}), expected)
          << simd::isaName(isa) << " " << threads;
    }
  }
  // Open at the top (the +y quad is the fifth): rays from above meet only faces wound away.
  for (raster::FrameTrace* t : {&all, &culled}) {
    core::Mesh& box = t->frame.occluders[0];
    box.indices.erase(box.indices.begin() + 24, box.indices.begin() + 30);
  }
  ASSERT_FALSE(raster::isClosedOutwardSurface(all.frame.occluders[0]));
  const auto open = raster::renderTrace(all, {simd::bestIsa(), 1, 32});
  const auto openCulled = raster::renderTrace(culled, {simd::bestIsa(), 1, 32});
  size_t lighter = 0;
  for (size_t i = 0; i < open.size(); ++i) lighter += openCulled[i] > open[i];
  EXPECT_GT(lighter, 100u);
}

TEST(Renderer, RejectsBadOptions) {
  const raster::FrameTrace t = testing::makeTestScene({});
  EXPECT_THROW(raster::Renderer(t.view, {simd::Isa::kScalar, 0, 32}), std::invalid_argument);
  EXPECT_THROW(raster::Renderer(t.view, {simd::Isa::kScalar, 1, 24}), std::invalid_argument);
  raster::StaticView singular = t.view;
  singular.cameraViewProj = core::Mat4{};
  EXPECT_THROW(raster::Renderer(singular, {}), raster::TraceError);
}

TEST(Renderer, RejectsAFrameThatDoesNotFitTheView) {
  raster::FrameTrace t = testing::makeTestScene({});
  raster::Renderer r(t.view, {});
  std::vector<uint8_t> out(t.frame.background.size());
  raster::FrameContent bad = t.frame;
  bad.passes[0].receiverTriangles[0] = 1u << 30;
  EXPECT_THROW(r.render(bad, out), raster::TraceError);
  bad = t.frame;
  bad.objects[0].mesh.positions[0].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(r.render(bad, out), raster::TraceError);
}

}  // namespace
}  // namespace penumbra
