// The kiosk draws a bundle's frames with the bundle's render settings (issue 17): a tuned
// pass ceiling and map size hold on the simulated board however generous its budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "firmware-sim/session.h"
#include "firmware-sim/sim_run.h"
#include "shadow/footprint_detail.h"
#include "shadow/frame_cost_model.h"
#include "shadow/render_settings.h"
#include "shadow/scene_bundle.h"
#include "tests/scratch_dir.h"

namespace penumbra::firmware_sim {
namespace {

TEST(BundleSettings, TheKioskKeepsToATunedBundlesCeilingAndMaps) {
  const std::filesystem::path dir = test::scratchPath("bundle-settings");
  std::filesystem::create_directories(dir);
  shadow::SceneBundle bundle =
      shadow::loadBundle(std::filesystem::path(PENUMBRA_DATA_DIR) / "showroom/showroom.bundle");
  bundle.settings.maxPasses = 6;
  bundle.settings.shadowMapSize = 128;
  bundle.settings.tuned = true;
  shadow::saveBundle(bundle, dir / "tuned.bundle");
  // A board that takes 1 ms a frame against a 33 ms budget: the controller climbs to its
  // ceiling at once.
  std::ofstream(dir / "session.json")
      << R"({"format": "penumbra-session", "version": 1, "bundle": "tuned.bundle",
      "frames": 40, "kiosk": {"max_passes": 64, "initial_passes": 8},
      "board": {"fixed_us": 1000, "per_pass_us": 0, "per_texel_ps": 0, "per_pixel_ps": 0}})";
  const Session session = loadSession(dir / "session.json");
  SimRun run(session, bestTargetOneThread());
  uint32_t most = 0;
  for (uint32_t i = 0; i < session.frames; ++i) {
    const kiosk::FrameReport r = run.step();
    EXPECT_LE(r.passesAsked, 6u) << "frame " << r.frame;
    EXPECT_EQ(r.shadowMapSize, 128u) << "frame " << r.frame;
    most = std::max(most, r.passesAsked);
  }
  EXPECT_EQ(most, 6u);
  std::filesystem::remove_all(dir);
}

// Per-frame detail (shadow/footprint_detail.h) in the kiosk: attract mode walks the product
// round the room while a board with time to spare lets the controller ask for its ceiling;
// every frame's passes and map stay within what the product's footprint allows (replayed
// here from the reported poses), the footprint does lower them, and they change by at most
// 4 passes a frame and one map rung at a time.
TEST(BundleSettings, TheProductsFootprintCapsPassesAndMapsFrameByFrame) {
  const std::filesystem::path dir = test::scratchPath("footprint-detail");
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(std::filesystem::path(PENUMBRA_DATA_DIR) / "showroom/showroom.bundle",
                             dir / "showroom.bundle");
  // Full detail from 400 pixels and 1 texel per pixel: the showroom's products (80-200
  // pixels across) then get fewer passes and smaller maps than the ceiling.
  std::ofstream(dir / "session.json")
      << R"({"format": "penumbra-session", "version": 1, "bundle": "showroom.bundle",
      "frames": 120, "kiosk": {"max_passes": 64, "initial_passes": 64, "attract_after_ms": 1,
      "attract_mdeg_per_s": 90000, "full_detail_px": 400, "texels_per_pixel": 1},
      "board": {"fixed_us": 1000, "per_pass_us": 0, "per_texel_ps": 0, "per_pixel_ps": 0}})";
  const Session session = loadSession(dir / "session.json");
  SimRun run(session, bestTargetOneThread());
  const shadow::SceneBundle& bundle = run.bundle().bundle;
  shadow::FootprintDetail replay(session.kiosk.footprintDetail, 64,
                                 shadow::shadowMapLadder(bundle.settings));
  std::vector<shadow::YawSphere> spheres;
  for (const shadow::ProductModel& p : bundle.products)
    spheres.push_back(shadow::yawSphere(p.mesh));
  uint32_t lowered = 0, lastPasses = 0, lastMap = 0;
  for (uint32_t i = 0; i < session.frames; ++i) {
    const kiosk::FrameReport r = run.step();
    const shadow::FootprintDetail::Limits l =
        replay.next(shadow::productFootprintPx(bundle.view, spheres[r.pose.product], r.pose));
    EXPECT_LE(r.passesAsked, l.passes) << "frame " << r.frame;
    EXPECT_LE(r.shadowMapSize, l.shadowMapSize) << "frame " << r.frame;
    lowered += l.passes < 64 || l.shadowMapSize < 256;
    if (i > 0) {
      EXPECT_LE(std::max(r.passesAsked, lastPasses) - std::min(r.passesAsked, lastPasses), 8u)
          << "frame " << r.frame;  // the controller's own step, or the footprint's 4
      EXPECT_TRUE(r.shadowMapSize == lastMap || r.shadowMapSize * 2 == lastMap ||
                  r.shadowMapSize == lastMap * 2)
          << "frame " << r.frame;
    }
    lastPasses = r.passesAsked;
    lastMap = r.shadowMapSize;
  }
  EXPECT_GT(lowered, session.frames / 2);
  std::filesystem::remove_all(dir);
}

// A product model replaced while the kiosk runs (kiosk/product_files.h) brings its own
// footprint: with full detail from 400 pixels the chair is capped at about 12 passes of 32;
// a 2.5 m cube dropped in its place is about 375 pixels across, and the cap climbs to about
// 30 by at most 4 passes a frame. Kept on the chair's sphere, it would stay at 12. (32, not
// the demo's 64, passes: under qemu-aarch64 each pass is dear.)
TEST(BundleSettings, AReplacedProductBringsItsOwnFootprint) {
  const std::filesystem::path dir = test::scratchPath("footprint-swap");
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(std::filesystem::path(PENUMBRA_DATA_DIR) / "showroom/showroom.bundle",
                             dir / "showroom.bundle");
  std::ofstream(dir / "cube.obj") << "v -1.25 0 -1.25\nv 1.25 0 -1.25\nv 1.25 0 1.25\n"
                                     "v -1.25 0 1.25\nv -1.25 2.5 -1.25\nv 1.25 2.5 -1.25\n"
                                     "v 1.25 2.5 1.25\nv -1.25 2.5 1.25\n"
                                     "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\n"
                                     "f 4 8 5 1\n";
  std::ofstream(dir / "session.json")
      << R"({"format": "penumbra-session", "version": 1, "bundle": "showroom.bundle",
      "frames": 30, "kiosk": {"max_passes": 32, "initial_passes": 32, "hud": "off",
      "full_detail_px": 400, "texels_per_pixel": 1},
      "product_files": [{"product": "chair", "file": "cube.obj", "at_ms": 300}],
      "board": {"fixed_us": 1000, "per_pass_us": 0, "per_texel_ps": 0, "per_pixel_ps": 0}})";
  const Session session = loadSession(dir / "session.json");
  SimRun run(session, bestTargetOneThread());
  uint32_t chairPasses = 0, last = 0;
  for (uint32_t i = 0; i < session.frames; ++i) {
    const kiosk::FrameReport r = run.step();
    ASSERT_EQ(r.pose.product, 0u);
    if (r.startNs < 300'000'000) chairPasses = r.passesAsked;
    if (i > 0) {
      EXPECT_LE(r.passesAsked, last + 4) << "frame " << r.frame;
    }
    last = r.passesAsked;
  }
  EXPECT_TRUE(run.log().contains("product chair: model")) << "the cube was not taken";
  EXPECT_GT(chairPasses, 0u);
  EXPECT_LE(chairPasses, 16u) << "the chair (about 150 px) is capped at about 12 passes";
  EXPECT_GE(last, 28u) << "the cube (about 375 px) lifts the cap to about 30";
  std::filesystem::remove_all(dir);
}

// The three differently lit showrooms (issue 17): their sessions run on the simulated board,
// the spotlight's single source casting one pass a frame, the skylight's 300 as many as the
// board affords.
TEST(BundleSettings, TheThreeShowroomsRun) {
  for (const char* name : {"spotlight", "daylight", "skylight"}) {
    const Session session = loadSession(std::filesystem::path(PENUMBRA_DATA_DIR) / "sessions" /
                                        (std::string(name) + ".json"));
    SimRun run(session, bestTargetOneThread());
    uint32_t most = 0;
    for (int i = 0; i < 40; ++i) most = std::max(most, run.step().passes);
    if (std::string(name) == "spotlight") {
      EXPECT_EQ(most, 1u) << name;
    } else {
      EXPECT_GT(most, 8u) << name;
    }
  }
}

// `penumbra tune` prices frames on the board the shipped sessions simulate: the constants
// must stay those sessions' board.
TEST(BundleSettings, TuneCostsFramesOnTheSessionsBoard) {
  const shadow::CostModel::Params pi4 = shadow::CostModel::raspberryPi4();
  for (const char* name : {"demo.json", "live.json", "soak.json", "faults.json", "spotlight.json",
                           "daylight.json", "skylight.json"}) {
    const Session s = loadSession(std::filesystem::path(PENUMBRA_DATA_DIR) / "sessions" / name);
    const shadow::CostModel::Params& b = s.cost;
    EXPECT_EQ(b.fixedNs, pi4.fixedNs) << name;
    EXPECT_EQ(b.perPassNs, pi4.perPassNs) << name;
    EXPECT_EQ(b.perTexelPs, pi4.perTexelPs) << name;
    EXPECT_EQ(b.perPixelPs, pi4.perPixelPs) << name;
    EXPECT_EQ(b.perPassVertexPs, pi4.perPassVertexPs) << name;
    EXPECT_EQ(b.perProductVertexPs, pi4.perProductVertexPs) << name;
    EXPECT_EQ(b.perShadedVertexPs, pi4.perShadedVertexPs) << name;
    EXPECT_EQ(b.perTransferredVertexPs, pi4.perTransferredVertexPs) << name;
    EXPECT_EQ(b.perPassTransferredVertexPs, pi4.perPassTransferredVertexPs) << name;
    EXPECT_EQ(b.perShadowMapTrianglePs, pi4.perShadowMapTrianglePs) << name;
  }
}

}  // namespace
}  // namespace penumbra::firmware_sim
