// The board program's configuration (kiosk/kiosk_config.h): the camera keys and the
// strictness that names the file and the key.
#include "kiosk/kiosk_config.h"

#include <gtest/gtest.h>

#include <fstream>
#include <numbers>

#include "envmap/fisheye_lens_file.h"
#include "tests/scratch_dir.h"

namespace penumbra::kiosk {
namespace {

std::filesystem::path write(const std::string& text) {
  const std::filesystem::path dir = test::scratchPath("kiosk-config");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "kiosk.json") << text;
  return dir / "kiosk.json";
}

TEST(KioskConfig, ReadsCameraControlsAndFallback) {
  const auto path = write(R"({"bundle": "room.bundle", "camera": "libcamera",
      "camera_id": "/base/soc/i2c0mux/i2c@1/imx219@10",
      "camera_controls": {"exposure_us": 12000, "analogue_gain": 2.0, "colour_gains": [1.8, 1.5]},
      "camera_fallback": "simulated", "display": "none",
      "product_files": [{"product": "chair", "file": "models/chair.obj"}]})");
  const KioskConfig c = loadKioskConfig(path);
  EXPECT_EQ(c.bundle, path.parent_path() / "room.bundle");
  EXPECT_EQ(c.camera, "libcamera");
  EXPECT_EQ(c.cameraId, "/base/soc/i2c0mux/i2c@1/imx219@10");
  EXPECT_EQ(c.cameraControls.exposureUs, 12000);
  EXPECT_EQ(c.cameraControls.analogueGain, 2.0f);
  EXPECT_EQ(c.cameraControls.redGain, 1.8f);
  EXPECT_EQ(c.cameraControls.blueGain, 1.5f);
  EXPECT_EQ(c.cameraFallback, "simulated");
  EXPECT_EQ(c.display, "none");
  ASSERT_EQ(c.productFiles.size(), 1u);
  EXPECT_EQ(c.productFiles[0].product, "chair");
  EXPECT_EQ(c.productFiles[0].file, path.parent_path() / "models" / "chair.obj");
  const KioskConfig d = loadKioskConfig(write(R"({"bundle": "b"})"));
  EXPECT_EQ(d.camera, "auto");
  EXPECT_EQ(d.cameraFallback, "photograph");
  EXPECT_EQ(d.cameraControls.exposureUs, CameraControls{}.exposureUs);
}

// What a site sets (issue 14): threads, GPIO wiring, the loop (frame rates, HUD), the camera's
// mounting; and the defaults a site gets without them.
TEST(KioskConfig, ReadsASitesWiringLoopAndCameraMounting) {
  const KioskConfig d = loadKioskConfig(write(R"({"bundle": "b"})"));
  EXPECT_EQ(d.threads, 0);  // one per core
  EXPECT_EQ(d.buttonLines, kDefaultButtonLines);
  EXPECT_EQ(d.ledLine, kDefaultLedLine);
  EXPECT_EQ(d.loop.hud, HudMode::kService);  // customers do not see the debug HUD
  EXPECT_EQ(d.loop.fastFrameNs, KioskOptions{}.fastFrameNs);
  EXPECT_TRUE(d.loop.cameraOrientation.identity());

  const KioskConfig c = loadKioskConfig(write(R"({"bundle": "b", "threads": 3,
      "gpio_lines": {"next": 17, "quality": 4}, "led_line": -1,
      "loop": {"fps": 25, "quality_fps": 10, "max_passes": 32, "hud": "on"},
      "camera_rotation": 180})"));
  EXPECT_EQ(c.threads, 3);
  EXPECT_EQ(c.buttonLines[static_cast<size_t>(Button::kNext)], 17u);
  EXPECT_EQ(c.buttonLines[static_cast<size_t>(Button::kQuality)], 4u);
  EXPECT_EQ(c.buttonLines[static_cast<size_t>(Button::kPrevious)], 6u);
  EXPECT_EQ(c.ledLine, -1);
  EXPECT_EQ(c.loop.fastFrameNs, 40'000'000);
  EXPECT_EQ(c.loop.qualityFrameNs, 100'000'000);
  EXPECT_EQ(c.loop.maxPasses, 32u);
  EXPECT_EQ(c.loop.hud, HudMode::kOn);
  EXPECT_TRUE(c.loop.cameraOrientation.mirrorX);  // upside down: both axes
  EXPECT_TRUE(c.loop.cameraOrientation.mirrorY);
  // A flip on top of the turn undoes that axis.
  const KioskConfig f = loadKioskConfig(
      write(R"({"bundle": "b", "camera_rotation": 180, "camera_flip": "vertical"})"));
  EXPECT_TRUE(f.loop.cameraOrientation.mirrorX);
  EXPECT_FALSE(f.loop.cameraOrientation.mirrorY);
  // The screen: SDL unless a site says; DRM with its card, or the first card with a screen.
  EXPECT_EQ(d.display, "sdl");
  const KioskConfig s = loadKioskConfig(
      write(R"({"bundle": "b", "display": "drm", "drm_device": "/dev/dri/card1"})"));
  EXPECT_EQ(s.display, "drm");
  EXPECT_EQ(s.drmDevice, "/dev/dri/card1");
  EXPECT_EQ(loadKioskConfig(write(R"({"bundle": "b", "display": "drm"})")).drmDevice, "");
}

// "environment": the real environment camera of live lighting and the lights' options.
TEST(KioskConfig, ReadsTheEnvironmentCamera) {
  EXPECT_FALSE(loadKioskConfig(write(R"({"bundle": "b"})")).environment.has_value());

  const auto path = write(R"({"bundle": "b", "environment": {"device": "/dev/video2",
      "width": 640, "height": 480, "lens": "equidistant180", "response": "srgb",
      "exposure_scale": 0.5, "samples": 128, "lights": 16, "yaw_deg": 90, "radiance_scale": 2,
      "stale_after_ms": 300}})");
  const KioskConfig c = loadKioskConfig(path);
  ASSERT_TRUE(c.environment.has_value());
  const EnvironmentCameraSettings& e = *c.environment;
  EXPECT_EQ(e.device, "/dev/video2");  // a device node is not a path of the configuration's
  EXPECT_EQ(e.width, 640u);
  EXPECT_EQ(e.height, 480u);
  EXPECT_TRUE(e.equidistant180);
  // The image circle is the shorter side's, centred: f = 240 / (π / 2).
  EXPECT_EQ(e.lens.width, 640u);
  EXPECT_EQ(e.lens.height, 480u);
  EXPECT_DOUBLE_EQ(e.lens.fx, 480 / 3.14159265358979323846);
  EXPECT_EQ(e.lens.fx, e.lens.fy);
  EXPECT_EQ(e.lens.cx, 320.0);
  EXPECT_EQ(e.lens.cy, 240.0);
  EXPECT_EQ(e.gamma, 0.0);  // sRGB
  EXPECT_EQ(e.exposureScale, 0.5);
  EXPECT_EQ(c.loop.liveLights.samples, 128u);
  EXPECT_EQ(c.loop.liveLights.maxLights, 16u);
  EXPECT_EQ(c.loop.liveLights.radianceScale, 2.0);
  EXPECT_EQ(c.loop.environmentStaleAfterNs, 300'000'000);
  EXPECT_NEAR(c.loop.liveLights.toWorld[0][2], 1.0, 1e-12);  // yaw 90°: image +x to room +z

  // A recording relative to the configuration, a calibrated lens, a gamma; the defaults.
  const auto path2 = write(R"({"bundle": "b", "environment": {"device": "footage/day.avi",
      "width": 480, "height": 480, "response": 2.2,
      "lens": {"fx": 148.5, "fy": 148, "cx": 239.5, "cy": 241, "k": [0.01, -0.002, 0, 0.0001]}}})");
  const KioskConfig d = loadKioskConfig(path2);
  ASSERT_TRUE(d.environment.has_value());
  EXPECT_EQ(d.environment->device, (path2.parent_path() / "footage" / "day.avi").string());
  EXPECT_FALSE(d.environment->equidistant180);
  EXPECT_EQ(d.environment->lens.fx, 148.5);
  EXPECT_EQ(d.environment->lens.cy, 241.0);
  EXPECT_EQ(d.environment->lens.k[1], -0.002);
  EXPECT_EQ(d.environment->lens.width, 480u);
  EXPECT_EQ(d.environment->gamma, 2.2);
  EXPECT_EQ(d.environment->exposureScale, 1.0);
  EXPECT_EQ(d.loop.liveLights.samples, envmap::LiveLightsOptions{}.samples);
  EXPECT_TRUE(d.environment->bracketUs.empty());
  EXPECT_FALSE(d.environment->response.has_value());

  // A calibrated response file beside the configuration and an exposure bracket: a device's
  // in steps of 100 µs with its settle frames, a recording's in any microseconds.
  CameraResponseCurves curves;
  for (size_t ch = 0; ch < 3; ++ch)
    for (size_t z = 0; z < 256; ++z)
      curves.logExposure[ch][z] = (double(z) - 128) / (40.0 + double(ch));
  writeCameraResponse(path.parent_path() / "response.json", curves);
  const KioskConfig b = loadKioskConfig(write(R"({"bundle": "b", "environment": {
      "device": "/dev/video2", "width": 480, "height": 480, "lens": "equidistant180",
      "response": "response.json", "bracket_us": [200, 1600, 12800], "settle_frames": 3}})"));
  ASSERT_TRUE(b.environment.has_value() && b.environment->response.has_value());
  EXPECT_EQ(b.environment->responseFile, (path.parent_path() / "response.json").string());
  EXPECT_EQ(b.environment->response->logExposure, curves.logExposure);
  EXPECT_EQ(b.environment->bracketUs, (std::vector<int64_t>{200, 1600, 12800}));
  EXPECT_EQ(b.environment->settleFrames, 3u);
  const KioskConfig r = loadKioskConfig(write(R"({"bundle": "b", "environment": {
      "device": "day_%03d.png", "width": 480, "height": 480, "lens": "equidistant180",
      "bracket_us": [250, 2000]}})"));
  EXPECT_EQ(r.environment->bracketUs, (std::vector<int64_t>{250, 2000}));
  EXPECT_EQ(r.environment->settleFrames, 2u);  // the default, unused by a recording
}

// A response file that cannot be used is refused naming the configuration, the key and the
// response file (kiosk/camera_response_file.h's own checks: camera_response_file_test.cpp).
TEST(KioskConfig, BadResponseFileNamesBothFiles) {
  const auto path = write(R"({"bundle": "b", "environment": {"device": "/dev/video2",
      "width": 480, "height": 480, "lens": "equidistant180", "response": "camera.json"}})");
  std::ofstream(path.parent_path() / "camera.json") << R"({"format": "penumbra-camera-response",
      "version": 1, "log_exposure": {"r": [0, 1], "g": [0, 1], "b": [0, 1]}})";
  try {
    loadKioskConfig(path);
    ADD_FAILURE() << "accepted a response of 2 codes";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              path.string() +
                  ": environment.response: " + (path.parent_path() / "camera.json").string() +
                  ": log_exposure.r: expected an array of 256 numbers, got an array of 2");
  }
}

// environment.lens as a lens file of `penumbra calibrate-fisheye` (envmap/fisheye_lens_file.h),
// relative to the configuration; its size must be the camera's and it must see the hemisphere.
TEST(KioskConfig, ReadsALensFileAndRefusesANarrowLens) {
  const auto path = write(R"({"bundle": "b", "environment": {"device": "/dev/video2",
      "width": 480, "height": 480, "lens": "lenses/env.json"}})");
  std::filesystem::create_directories(path.parent_path() / "lenses");
  const std::filesystem::path lensPath = path.parent_path() / "lenses" / "env.json";
  envmap::FisheyeLensFile f;
  f.lens = {480, 480, 146.2, 145.9, 240.3, 239.6, {0.02, -0.005, 0.001, -0.0002}};
  f.rmsPx = 0.05;
  f.views = 13;
  envmap::writeFisheyeLensFile(lensPath, f);
  const KioskConfig c = loadKioskConfig(path);
  ASSERT_TRUE(c.environment.has_value());
  EXPECT_EQ(c.environment->lensFile, lensPath.string());
  EXPECT_FALSE(c.environment->equidistant180);
  EXPECT_EQ(c.environment->lens.fy, 145.9);
  EXPECT_EQ(c.environment->lens.k[3], -0.0002);
  EXPECT_EQ(c.environment->lensReach, envmap::nearestEdgeReach(f.lens));
  EXPECT_GT(c.environment->lensReach * 180 / std::numbers::pi, 90.0);

  const auto refusal = [&] {
    try {
      loadKioskConfig(path);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // Another size than the camera's.
  f.lens.width = 640;
  envmap::writeFisheyeLensFile(lensPath, f);
  EXPECT_EQ(refusal(), path.string() + ": environment.lens: " + lensPath.string() +
                           ": calibrated for 640x480 images, the environment camera's are 480x480");
  // A lens of f = 165 on 480 pixels: 240 / 165 rad = 83.34° to the nearest edge.
  f.lens = {480, 480, 165, 165, 240, 240, {}};
  envmap::writeFisheyeLensFile(lensPath, f);
  EXPECT_EQ(refusal(), path.string() + ": environment.lens: " + lensPath.string() +
                           " sees 83.34 deg from its axis towards the nearest image edge: the "
                           "hemisphere map needs 90 deg (a wider lens, or the lens centred in "
                           "the image)");
  // A bad field names both files.
  std::ofstream(lensPath) << R"({"format": "penumbra-fisheye-lens", "version": 1,
      "image_size": [480, 480], "fx": 146, "fy": 146, "cx": 240, "cy": 500,
      "k": [0, 0, 0, 0], "rms_px": 0.1, "views": 5})";
  EXPECT_EQ(refusal(), path.string() + ": environment.lens: " + lensPath.string() +
                           ": cy: 500 is outside the image (0 < cy < 480)");
  // The same reach rule for intrinsics written inline.
  const auto inline165 = write(R"({"bundle": "b", "environment": {"device": "/dev/video2",
      "width": 480, "height": 480, "lens": {"fx": 165, "fy": 165, "cx": 240, "cy": 240,
      "k": [0, 0, 0, 0]}}})");
  try {
    loadKioskConfig(inline165);
    ADD_FAILURE() << "accepted a lens of 83 degrees";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("environment.lens: the lens sees 83.34 deg"),
              std::string::npos)
        << e.what();
  }
}

TEST(KioskConfig, BadValuesNameTheFileAndKey) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {R"({"bundle": "b", "camera_controls": {"exposure_us": 0}})",
       "camera_controls: exposure_us must be in [1, 10000000] (got 0)"},
      {R"({"bundle": "b", "camera_controls": {"exposure_us": 1.5}})",
       "camera_controls.exposure_us: expected an integer, got 1.5"},
      {R"({"bundle": "b", "camera_controls": {"analogue_gain": 0.5}})",
       "analogue_gain must be in [1, 64]"},
      {R"({"bundle": "b", "camera_controls": {"colour_gains": [1.0]}})",
       "camera_controls.colour_gains: expected an array of 2 numbers, got an array of 1"},
      {R"({"bundle": "b", "camera_controls": {"iso": 100}})", "camera_controls.iso: unknown field"},
      {R"({"bundle": "b", "camera": "usb"})", "camera: 'auto', 'libcamera'"},
      {R"({"bundle": "b", "camera_fallback": "black"})",
       "camera_fallback: expected one of \"photograph\", \"simulated\", got \"black\""},
      {R"({"bundle": "b", "screen": "big"})", "screen: unknown field"},
      {R"({"bundle": "b", "product_files": [{"product": "chair"}]})",
       "product_files[0].file: missing"},
      {R"({"camera": "auto"})", "bundle: required"},
      {R"({"bundle": "b", "threads": 65})", "threads: "},
      {R"({"bundle": "b", "camera_rotation": 90})", "camera_rotation: expected 0 or 180, got 90"},
      {R"({"bundle": "b", "camera_flip": "diagonal"})", "camera_flip: expected one of"},
      {R"({"bundle": "b", "gpio_lines": {"jump": 3}})", "gpio_lines.jump: not a button"},
      {R"({"bundle": "b", "gpio_lines": {"next": 6}})",
       "gpio_lines: next and previous are both on line 6"},
      {R"({"bundle": "b", "led_line": 21})",
       "led_line: the LED and the quality button are both on line 21"},
      {R"({"bundle": "b", "gpio_lines": {"left": 12}})",
       "gpio_lines: the LED and the left button are both on line 12"},
      {R"({"bundle": "b", "loop": {"hud": true}})", "loop.hud: "},
      {R"({"bundle": "b", "display": "fbdev"})",
       "display: expected one of \"drm\", \"sdl\", \"none\", got \"fbdev\""},
      {R"({"bundle": "b", "drm_device": "/dev/dri/card1"})",
       "drm_device: is for display \"drm\", and display is \"sdl\""},
      {R"({"bundle": "b", "loop": {"hud": "maybe"}})",
       "loop.hud: expected one of \"on\", \"off\", \"service\", got \"maybe\""},
      {R"({"bundle": "b", "loop": {"fps": 0}})", "loop.fps: "},
      {R"({"bundle": "b", "loop": {"service_hold_ms": 6000}})",
       "loop.service_hold_ms: the service hold (6000 ms) must be shorter than stuck_after_ms "
       "(5000 ms)"},
      {R"({"bundle": "b", "loop": {"stuck_after_ms": 2000}})",
       "loop.stuck_after_ms: the service hold (3000 ms) must be shorter"},
      {R"({"bundle": "b", "loop": {"speed": 2}})", "loop.speed: unknown field"},
      {R"({"bundle": )", "line 1: "},
      {R"({"bundle": "b", "environment": "/dev/video2"})",
       "environment: expected an object, got a string"},
      {R"({"bundle": "b", "environment": {"width": 480, "height": 480, "lens": "equidistant180"}})",
       "environment.device: missing"},
      {R"({"bundle": "b", "environment": {"device": "", "width": 480, "height": 480,
          "lens": "equidistant180"}})",
       "environment.device: expected a non-empty string"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "fps": 30}})",
       "environment.fps: unknown field"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 1, "height": 480,
          "lens": "equidistant180"}})",
       "environment.width: 1 is not in [2, 4096]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480,
          "lens": "equidistant180"}})",
       "environment.height: missing"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480}})",
       "environment.lens: missing"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "pinhole"}})",
       "environment.lens: \"pinhole\": no such lens file ("},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": 180}})",
       "environment.lens: expected \"equidistant180\", a lens file or {\"fx\""},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": {"fx": 150, "fy": 150, "cx": 240, "cy": 240}}})",
       "environment.lens.k: missing"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": {"fx": 150, "fy": 150, "cx": 240, "cy": 240, "k": [0, 0, 0]}}})",
       "environment.lens.k: expected an array of 4 numbers, got an array of 3"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": {"fx": 0, "fy": 150, "cx": 240, "cy": 240, "k": [0, 0, 0, 0]}}})",
       "environment.lens.fx: 0 is not in"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": {"fx": 150, "fy": 150, "cx": 481, "cy": 240, "k": [0, 0, 0, 0]}}})",
       "environment.lens.cx: 481 is not in [0, 480]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": {"fx": 150, "fy": 150, "cx": 240, "cy": 240, "k": [0, 0, 0, 0], "k5": 0}}})",
       "environment.lens.k5: unknown field"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "response": "linear"}})",
       "environment.response: \"linear\": no such response file ("},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "response": 0.45}})",
       "environment.response: 0.45 is not in [1, 4]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "response": true}})",
       "environment.response: expected \"srgb\", a gamma (a number in [1, 4]) or a response "
       "file"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "exposure_scale": 0}})",
       "environment.exposure_scale: 0 is not in"},
      // The exposure bracket (docs/kiosk.md, "Environment camera").
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [2000, 200, 16000]}})",
       "environment.bracket_us[1]: must be longer than the exposure before it (2000 us)"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [200, 200]}})",
       "environment.bracket_us[1]: must be longer than the exposure before it (200 us)"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [0, 2000]}})",
       "environment.bracket_us[0]: 0 is not in [1, 1000000]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [-100]}})",
       "environment.bracket_us[0]: -100 is not in [1, 1000000]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": []}})",
       "environment.bracket_us: expected an array of 1 to 8 elements, got 0"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [100, 200, 300, 400, 500, 600, 700, 800, 900]}})",
       "environment.bracket_us: expected an array of 1 to 8 elements, got 9"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [250, 2000]}})",
       "environment.bracket_us[0]: a V4L2 device's exposure is set in steps of 100 us"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [200, 2000], "settle_frames": 31}})",
       "environment.settle_frames: 31 is not in [0, 30]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [200, 2000], "settle_frames": -1}})",
       "environment.settle_frames: -1 is not in [0, 30]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "settle_frames": 2}})",
       "environment.settle_frames: only with bracket_us"},
      {R"({"bundle": "b", "environment": {"device": "day_%03d.png", "width": 480, "height": 480,
          "lens": "equidistant180", "bracket_us": [250, 2000], "settle_frames": 2}})",
       "environment.settle_frames: only for a device: frame i of a recording was shot with "
       "bracket_us[i % n]"},
      {R"({"bundle": "b", "environment": {"device": "/dev/video2", "width": 480, "height": 480,
          "lens": "equidistant180", "samples": 8, "lights": 9}})",
       "environment.lights: must not exceed samples"},
      {R"({"bundle": "b", "camera": "/dev/video2", "environment": {"device": "/dev/video2",
          "width": 480, "height": 480, "lens": "equidistant180"}})",
       "environment.device: the room camera is /dev/video2 too"},
  };
  for (const auto& [text, expected] : cases) {
    const auto path = write(text);
    try {
      loadKioskConfig(path);
      ADD_FAILURE() << "accepted " << text;
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace penumbra::kiosk
