#include "firmware-sim/session_stats.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "firmware-sim/session.h"
#include "firmware-sim/sim_run.h"
#include "tests/scratch_dir.h"

namespace penumbra::firmware_sim {
namespace {

kiosk::FrameReport frame(int64_t startNs, int64_t latencyNs, bool stale) {
  kiosk::FrameReport r;
  r.startNs = startNs;
  r.endNs = startNs + 20;
  r.latencyNs = latencyNs;
  r.stale = stale;
  return r;
}

TEST(SessionStats, OutagesAreCountedApartFromLatency) {
  SessionStats s(16);
  s.add(frame(0, -1, true));     // no camera frame yet: neither
  s.add(frame(100, 30, false));  // live
  s.add(frame(200, 150, true));  // outage 1: 200 .. 400
  s.add(frame(300, 250, true));
  s.add(frame(400, 30, false));
  s.add(frame(500, 31, false));
  s.add(frame(600, 130, true));  // outage 2, open at the end: 600 .. 720
  s.add(frame(700, 230, true));
  s.finish();
  EXPECT_EQ(s.outages(), 2u);
  EXPECT_EQ(s.outageTotalNs(), 200 + 120);
  EXPECT_EQ(s.longestOutageNs(), 200);
  EXPECT_EQ(s.liveLatencyNs(), (std::vector<int64_t>{30, 30, 31}));
  EXPECT_EQ(percentile(s.liveLatencyNs(), 99), 31);
  EXPECT_EQ(percentile({}, 50), -1);
}

TEST(SessionStats, ATwoSecondDisconnectIsAnOutageNotLatency) {
  // The faults session's disconnect: 60 camera frames (2 s) never come.
  const std::filesystem::path dir = test::scratchPath("session-stats");
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "disconnect.json";
  std::ofstream(file)
      << R"({"format": "penumbra-session", "version": 1, "bundle": ")"
      << (std::filesystem::path(PENUMBRA_DATA_DIR) / "showroom/showroom.bundle").string()
      << R"(", "frames": 150, "kiosk": {"max_passes": 8},
      "board": {"fixed_us": 7000, "per_pass_us": 0, "per_texel_ps": 2000, "per_pixel_ps": 14000},
      "camera": {"faults": [{"kind": "disconnect", "frame": 30, "count": 60}]}})";
  const Session session = loadSession(file);
  SimRun run(session, bestTargetOneThread());
  SessionStats stats(session.frames);
  for (uint32_t i = 0; i < session.frames; ++i) stats.add(run.step());
  stats.finish();
  EXPECT_EQ(stats.outages(), 1u);
  // Frozen once the last frame is older than 100 ms, live again at the first new frame
  // after the reopen (tried every second): about 2 s.
  EXPECT_GE(stats.longestOutageNs(), 1'800'000'000);
  EXPECT_LE(stats.longestOutageNs(), 3'200'000'000);
  EXPECT_EQ(stats.outageTotalNs(), stats.longestOutageNs());
  // The latency of live frames only: at most stale_after_ms (100 ms) old when the frame
  // starts, plus that frame's work (≤ one 33 ms period); never the 2 s outage.
  EXPECT_LE(percentile(stats.liveLatencyNs(), 99), 133'333'334);
  EXPECT_LE(percentile(stats.liveLatencyNs(), 50), 50'000'000);
  EXPECT_GE(stats.liveLatencyNs().size(), 80u);  // 150 frames less the outage
}

}  // namespace
}  // namespace penumbra::firmware_sim
