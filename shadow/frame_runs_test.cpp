// The loop runs of the tools on the bundled showroom: the profile's sliding product and its
// last-frame counts, the median, and the controller settling under a generous budget.
#include "shadow/frame_runs.h"
#include "tests/showroom_bundle.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace penumbra::shadow {
namespace {

TEST(FrameRuns, MedianOfOddEvenAndEmpty) {
  EXPECT_EQ(median({3, 1, 2}), 2.0);
  EXPECT_EQ(median({4, 1, 2, 3}), 2.5);
  EXPECT_EQ(median({}), 0.0);
}

TEST(FrameRuns, ProfileSlidesTheProductAndReportsTheLastFrame) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  const PassProfile p = profilePasses(loop, b.startPose, 3, 2);
  EXPECT_EQ(loop.frameNumber, 3u) << "one warm-up frame and two timed ones";
  EXPECT_EQ(p.passesAsked, 3u);
  EXPECT_EQ(p.passes, loop.stats.passes);
  EXPECT_LE(p.passes, 3u);
  EXPECT_GT(p.passes, 0u) << "the product shadows the floor at the start pose";
  EXPECT_EQ(p.shadowedPixels, loop.renderer.lastStats().passPixels);
  EXPECT_EQ(p.shadowMapTriangles, loop.renderer.lastStats().shadowMapTriangles);
  EXPECT_GT(p.total, 0.0);

  // The same frames stepped by hand: frame f slides the product by 0.01 * (f % 7).
  FrameLoop byHand(b, 256, {});
  for (int f = 0; f < 3; ++f) {
    ProductPose pose = b.startPose;
    pose.x += 0.01f * float(f % 7);
    byHand.step(pose, 3);
  }
  EXPECT_EQ(byHand.rgba, loop.rgba);
}

TEST(FrameRuns, AGenerousBudgetRaisesThePasses) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  // One second a frame.
  const FrameRateController::Options o = renderControllerOptions(1.0, b.settings);
  EXPECT_EQ(o.initialPasses, 8u);
  EXPECT_EQ(o.maxPasses, b.settings.maxPasses);
  // 1 ms a frame against a budget of one second: the controller must add passes. A cost
  // model, not the wall clock, so a loaded machine (a frame can take a second under ASan)
  // cannot change the outcome.
  const auto oneMillisecond = [](const FrameLoop&) { return int64_t{1'000'000}; };
  const FrameRateController::Decision d = settleFrameRate(loop, b.startPose, o, 6, oneMillisecond);
  EXPECT_EQ(loop.frameNumber, 6u);
  EXPECT_GT(d.passes, o.initialPasses);
  EXPECT_EQ(d.shadowMapSize, 256u);
  for (const raster::ShadowPass& pass : loop.frame.passes) EXPECT_EQ(pass.shadowMapSize, 256u);
  EXPECT_THROW(renderControllerOptions(0.0, b.settings), std::invalid_argument);
}

// A bundle's settings bound what the controller may pick: a tuned ceiling of 6 passes and
// 128-texel maps hold however generous the budget.
TEST(FrameRuns, TheBundlesSettingsBoundTheController) {
  const SceneBundle& b = testing::showroomBundle();
  RenderSettings tuned = b.settings;
  tuned.maxPasses = 6;
  tuned.shadowMapSize = 128;
  const FrameRateController::Options o = renderControllerOptions(1.0, tuned);
  EXPECT_EQ(o.initialPasses, 6u);
  EXPECT_EQ(o.minPasses, 4u);
  EXPECT_EQ(o.shadowMapSizes, (std::vector<uint32_t>{128, 64, 32}));
  FrameLoop loop(b, compositorOptions(tuned), {});
  const auto oneMillisecond = [](const FrameLoop&) { return int64_t{1'000'000}; };
  const FrameRateController::Decision d = settleFrameRate(loop, b.startPose, o, 6, oneMillisecond);
  EXPECT_EQ(d.passes, 6u);
  EXPECT_EQ(d.shadowMapSize, 128u);
  for (const raster::ShadowPass& pass : loop.frame.passes) EXPECT_LE(pass.shadowMapSize, 256u);
}

}  // namespace
}  // namespace penumbra::shadow
