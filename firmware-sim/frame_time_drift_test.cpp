#include "firmware-sim/frame_time_drift.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <vector>

#include "firmware-sim/soak.h"
#include "scene/sha256.h"

namespace penumbra::firmware_sim {
namespace {

TEST(FrameTimeDrift, PairedMedianRatio) {
  const std::vector<int64_t> first{100, 200, 300, 400, 0}, same = first;
  EXPECT_DOUBLE_EQ(pairedMedianRatio(first, same), 1.0);
  // Every frame a quarter slower but one, which is much faster: the median ignores it.
  const std::vector<int64_t> slower{125, 250, 375, 40, 7};
  EXPECT_DOUBLE_EQ(pairedMedianRatio(first, slower), 1.25);
  // Even count: the mean of the two middle ratios (1.0 and 1.5); the zero pair left out.
  const std::vector<int64_t> mixed{100, 300, 300, 800, 1};
  EXPECT_DOUBLE_EQ(pairedMedianRatio(first, mixed), 1.25);
  EXPECT_EQ(pairedMedianRatio({}, {}), 0.0);
  EXPECT_THROW(pairedMedianRatio(first, std::vector<int64_t>{1, 2}), std::invalid_argument);
}

Session shortSoak() {
  return soakSession(loadSession(std::filesystem::path(PENUMBRA_DATA_DIR) / "sessions/soak.json"),
                     24);
}

void record(FrameTimeDrift& drift, const Session& s) {
  SimRun run(s, bestTargetOneThread());
  for (uint32_t f = 0; f < s.frames; ++f) {
    const kiosk::FrameReport r = run.step();
    drift.add(r, scene::sha256(run.frame()));
  }
}

TEST(FrameTimeDrift, ReplaysTheRecordedFramesToTheSameBytes) {
  const Session s = shortSoak();
  FrameTimeDrift drift(16);  // the first 16 of 24 frames
  record(drift, s);
  ASSERT_EQ(drift.recorded(), 16u);
  const FrameTimeDrift::Result r = drift.replay(s, bestTargetOneThread(), 9);
  EXPECT_EQ(r.firstFrame, 9u);
  EXPECT_EQ(r.lastFrame, 16u);
  EXPECT_GT(r.firstMedianMs, 0.0);
  EXPECT_GT(r.replayMedianMs, 0.0);
  EXPECT_GT(r.ratio, 0.0);
  EXPECT_THROW(drift.replay(s, bestTargetOneThread(), 17), std::invalid_argument);
  EXPECT_THROW(drift.replay(s, bestTargetOneThread(), 0), std::invalid_argument);
}

// A replay of other frames is refused, naming the first that differs (here a press at the
// start moves the product).
TEST(FrameTimeDrift, AReplayThatDrawsOtherFramesIsRefused) {
  const Session s = shortSoak();
  FrameTimeDrift drift(24);
  record(drift, s);
  Session moved = s;
  ScriptedPress p;
  p.atNs = 0;
  p.button = kiosk::Button::kRight;
  moved.presses.insert(moved.presses.begin(), p);
  try {
    drift.replay(moved, bestTargetOneThread(), 1);
    FAIL() << "a replay of other frames was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("differs from the same frame of the first run"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace penumbra::firmware_sim
