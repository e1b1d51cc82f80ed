// Stage times: a frame's stages add up to the frame (FrameLoop), and over many frames the
// stages' means add up to the mean frame (FrameStageSamples).
#include "shadow/frame_stages.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "shadow/frame_loop.h"
#include "tests/showroom_bundle.h"

namespace penumbra::shadow {
namespace {

TEST(FrameStages, TheLoopsStagesSumToItsFrameExactly) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  for (uint32_t f = 0; f < 3; ++f) {
    ProductPose pose = b.startPose;
    pose.x += 0.05f * float(f);
    loop.step(pose, 8);
    const int64_t sum = std::accumulate(loop.stages.ns.begin(), loop.stages.ns.end(), int64_t{0});
    EXPECT_EQ(sum, loop.frameNs) << "frame " << f;
    EXPECT_EQ(loop.stages.boardNs(), loop.frameNs);
    for (FrameStage s : {FrameStage::kTraversal, FrameStage::kRoomTransfers, FrameStage::kPassList,
                         FrameStage::kRasterPasses}) {
      EXPECT_GT(loop.stages[s], 0) << frameStageName(s) << ", frame " << f;
    }
    // The kiosk's own stages are its to fill.
    EXPECT_EQ(loop.stages[FrameStage::kCamera], 0);
    EXPECT_EQ(loop.stages[FrameStage::kHud], 0);
  }
}

TEST(FrameStages, MeansAddUpAndPercentilesAreNearestRank) {
  FrameStageSamples samples;
  samples.reserve(60);  // fewer than added: the rest grow as needed; only added ones count
  for (int64_t f = 1; f <= 100; ++f) {
    FrameStages s;
    s[FrameStage::kRasterPasses] = f * 1'000'000;  // 1..100 ms
    s[FrameStage::kRoomTransfers] = 250'000;
    s[FrameStage::kSimulatorCamera] = 7'000'000;  // not the board's
    samples.add(s);
  }
  EXPECT_EQ(samples.frames(), 100u);
  EXPECT_DOUBLE_EQ(samples.meanMs(FrameStage::kRasterPasses), 50.5);
  EXPECT_DOUBLE_EQ(samples.meanBoardMs(), 50.75);
  EXPECT_DOUBLE_EQ(
      samples.meanMs(FrameStage::kRasterPasses) + samples.meanMs(FrameStage::kRoomTransfers),
      samples.meanBoardMs());
  EXPECT_DOUBLE_EQ(samples.percentileMs(FrameStage::kRasterPasses, 50), 51);
  EXPECT_DOUBLE_EQ(samples.percentileMs(FrameStage::kRasterPasses, 99), 100);
  const std::string table = samples.table();
  EXPECT_NE(table.find("raster passes"), std::string::npos) << table;
  EXPECT_NE(table.find("simulator camera"), std::string::npos) << table;
  EXPECT_EQ(table.find("observe"), std::string::npos) << "stages that took no time are left out";
}

TEST(FrameStages, CsvHasAColumnPerStageAndALinePerAddedFrame) {
  FrameStageSamples samples;
  samples.reserve(8);  // more than added: only added frames are lines
  for (int64_t f = 1; f <= 3; ++f) {
    FrameStages s;
    s[FrameStage::kPassList] = f * 1'500'000;
    s[FrameStage::kHud] = 250'000;
    s[FrameStage::kSimulatorCamera] = 9'000'000;  // a column, not in board_frame
    samples.add(s);
  }
  const std::string csv = samples.csv();
  std::vector<std::string> lines;
  for (size_t at = 0, end; (end = csv.find('\n', at)) != std::string::npos; at = end + 1) {
    lines.push_back(csv.substr(at, end - at));
  }
  ASSERT_EQ(lines.size(), 4u) << csv;
  EXPECT_EQ(std::count(lines[0].begin(), lines[0].end(), ','), int(kFrameStageCount) + 1);
  EXPECT_EQ(lines[0].rfind("frame,camera,", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(",pass_list,"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find(",simulator_camera,board_frame"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[2].rfind("2,", 0), 0u) << lines[2];
  EXPECT_NE(lines[2].find(",3.000,"), std::string::npos) << lines[2];       // pass list
  EXPECT_NE(lines[2].find(",9.000,3.250"), std::string::npos) << lines[2];  // camera, board
}

}  // namespace
}  // namespace penumbra::shadow
