// Live lighting on the simulated board (issue 16): a session whose environment camera plays a
// fisheye EXR sequence lights the product and moves its shadow; a camera that hangs or sends
// a frame the kiosk cannot use is said on the HUD, in the log and by the LED, and the last
// good lights stay; sessions naming a bad environment are refused with the reason.
#ifdef PENUMBRA_HAVE_FOOTAGE
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "envmap/fisheye_resampler.h"
#include "firmware-sim/session.h"
#include "firmware-sim/sim_run.h"
#include "tests/scratch_dir.h"

namespace penumbra::firmware_sim::live_lighting_test {
namespace {

namespace fs = std::filesystem;

const fs::path kBundle = fs::path(PENUMBRA_DATA_DIR) / "showroom" / "showroom.bundle";

// `count` fisheye frames of a dim sky with one bright lamp 40° above the horizon, turned 45°
// about the zenith per frame.
fs::path lampSequence(const std::string& name, int count) {
  const fs::path dir = test::scratchPath("live-lighting-session") / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  core::ImageF latLong(128, 64);
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 128; ++x)
      for (int c = 0; c < 3; ++c)
        latLong.pixel(x, y)[c] = (x >= 20 && x < 26 && y >= 14 && y < 20) ? 400.0f : 0.3f;
  const envmap::FisheyeLens lens = envmap::FisheyeLens::equidistant180(96);
  for (int k = 0; k < count; ++k) {
    const core::ImageF image = envmap::renderFisheye(latLong, lens, 45.0 * k);
    cv::Mat bgr(int(image.height), int(image.width), CV_32FC3);
    for (uint32_t y = 0; y < image.height; ++y)
      for (uint32_t x = 0; x < image.width; ++x)
        for (int c = 0; c < 3; ++c) bgr.at<cv::Vec3f>(int(y), int(x))[2 - c] = image.pixel(x, y)[c];
    const std::string file = "env_" + std::to_string(k) + ".exr";
    EXPECT_TRUE(cv::imwrite((dir / file).string(), bgr));
  }
  return dir;
}

Session liveSession(const std::string& name, const std::string& environment, uint32_t frames) {
  const fs::path dir = test::scratchPath("live-lighting-session");
  fs::create_directories(dir);
  const fs::path file = dir / (name + ".json");
  std::ofstream(file) << R"({"format": "penumbra-session", "version": 1, "bundle": ")"
                      << kBundle.string() << "\", \"frames\": " << frames << R"(,
      "kiosk": {"max_passes": 16, "initial_passes": 8},
      "board": {"fixed_us": 7000, "per_pass_us": 0, "per_texel_ps": 2000, "per_pixel_ps": 14000},
      "environment": )"
                      << environment << "}";
  return loadSession(file);
}

bool warned(const kiosk::FrameReport& r, const std::string& text) {
  for (const std::string& w : r.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

TEST(KioskLiveLighting, EnvironmentFramesLightTheProductAndMoveItsShadow) {
  const fs::path frames = lampSequence("turning", 8);
  const Session s = liveSession(
      "turning", R"({"frames": ")" + frames.string() + R"(", "fps": 10, "samples": 64, "lights": 8,
          "radiance_scale": 0.05})",
      12);
  SimRun run(s, bestTargetOneThread());
  EXPECT_TRUE(run.log().contains("live lighting:"));
  std::vector<std::vector<uint8_t>> shown;
  for (int i = 0; i < 12; ++i) {
    const kiosk::FrameReport r = run.step();
    EXPECT_TRUE(r.liveLighting) << "frame " << r.frame << ": the first map arrives at 0";
    EXPECT_LE(r.passes, 8u) << "at most `lights` passes";
    EXPECT_GT(r.passes, 0u);
    EXPECT_FALSE(warned(r, "ENVIRONMENT")) << "frame " << r.frame;
    EXPECT_GT(r.stages[shadow::FrameStage::kEnvironment], 0);
    shown.push_back(run.frame());
  }
  // The lamp turns 45° every 100 ms and the kiosk runs at 30 fps: frames 1 and 4 see
  // different maps, so the product's shading and its shadow differ.
  EXPECT_NE(shown[0], shown[4]);
  // The same session again: the same bytes (virtual clock, fixed-order arithmetic).
  SimRun again(s, bestTargetOneThread());
  for (int i = 0; i < 12; ++i) {
    again.step();
    EXPECT_EQ(again.frame(), shown[size_t(i)]) << "frame " << i + 1;
  }
}

TEST(KioskLiveLighting, AFrozenEnvironmentCameraIsSaidAndItsLastLightsKept) {
  const fs::path frames = lampSequence("frozen", 4);
  const Session s = liveSession("frozen", R"({"frames": ")" + frames.string() + R"(", "fps": 20,
          "samples": 32, "lights": 4, "stop_at_ms": 150, "stale_after_ms": 300})",
                                30);
  SimRun run(s, bestTargetOneThread());
  bool said = false;
  for (int i = 0; i < 30; ++i) {
    const kiosk::FrameReport r = run.step();
    EXPECT_TRUE(r.liveLighting) << "frame " << r.frame << ": the last lights stay";
    const bool frozen = r.startNs > 100'000'000 + 300'000'000 + 50'000'000;
    if (frozen) {
      EXPECT_TRUE(warned(r, "ENVIRONMENT FROZEN - LAST LIGHTS")) << "frame " << r.frame;
      EXPECT_NE(r.led, kiosk::LedState::kReady);
      said = true;
    }
  }
  EXPECT_TRUE(said) << "the session outlasts the stale time";
  EXPECT_TRUE(run.log().contains("environment camera: no new frame, the last lights kept"));
  EXPECT_FALSE(run.log().contains("environment camera: no new frame", 400'000'000))
      << "said when it happens, not before";
}

TEST(KioskLiveLighting, ABadEnvironmentIsRefusedNamingTheField) {
  const fs::path frames = lampSequence("refused", 2);
  const auto refused = [](const std::string& name, const std::string& environment,
                          const std::string& expected) {
    try {
      const Session s = liveSession(name, environment, 5);
      SimRun run(s, bestTargetOneThread());
      ADD_FAILURE() << name << ": accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused("missing", R"({"frames": "no-such-folder"})", "environment.frames");
  refused("lights", R"({"frames": ")" + frames.string() + R"(", "samples": 8, "lights": 9})",
          "lights");
  refused("unknown", R"({"frames": ")" + frames.string() + R"(", "lamp": 1})", "lamp");
  refused("scale", R"({"frames": ")" + frames.string() + R"(", "radiance_scale": 0})",
          "radiance_scale");
}

}  // namespace
}  // namespace penumbra::firmware_sim::live_lighting_test
#endif  // PENUMBRA_HAVE_FOOTAGE
