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
  const FrameRateController::Options o = renderControllerOptions(1.0);  // one second a frame
  EXPECT_EQ(o.initialPasses, 8u);
  // 1 ms a frame against a budget of one second: the controller must add passes. A cost
  // model, not the wall clock, so a loaded machine (a frame can take a second under ASan)
  // cannot change the outcome.
  const auto oneMillisecond = [](const FrameLoop&) { return int64_t{1'000'000}; };
  const FrameRateController::Decision d = settleFrameRate(loop, b.startPose, o, 6, oneMillisecond);
  EXPECT_EQ(loop.frameNumber, 6u);
  EXPECT_GT(d.passes, o.initialPasses);
  EXPECT_EQ(d.shadowMapSize, 256u);
  for (const raster::ShadowPass& pass : loop.frame.passes) EXPECT_EQ(pass.shadowMapSize, 256u);
  EXPECT_THROW(renderControllerOptions(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
