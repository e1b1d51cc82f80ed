// The real environment camera (platform/opencv_environment_camera.h) through the module the
// kiosk loads (opencv_camera_module.h), on recordings this test writes: a synthetic room with
// one bright lamp in a known direction, photographed by an equidistant fisheye
// (envmap::renderFisheye) and encoded to 8 bits with the sRGB curve. The map must put the lamp
// where it is and give back the radiance the frames encode; missing and vanishing sources are
// refused or disconnected with a message; saturated lamps are said.
#if defined(PENUMBRA_HAVE_OPENCV_CAMERA) && defined(PENUMBRA_HAVE_FOOTAGE)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

#include "core/colour.h"
#include "envmap/fisheye_resampler.h"
#include "envmap/hemisphere_map.h"
#include "platform/environment_response.h"
#include "platform/hardware.h"
#include "platform/opencv_camera_module.h"
#include "tests/scratch_dir.h"

namespace penumbra::platform {
namespace {

constexpr uint32_t kSize = 240;
constexpr int64_t kMs = 1'000'000;

// Azimuth 60° (counter-clockwise from the image's +x), 40° from the zenith.
glm::dvec3 lampDirection() {
  const double theta = 40 * std::numbers::pi / 180, phi = 60 * std::numbers::pi / 180;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// A lat-long room (envmap/lat_long.h's layout): a dim sky brighter towards the zenith and a
// lamp of radiance `lamp` within 6° of lampDirection().
core::ImageF room(float lamp) {
  core::ImageF latLong(256, 128);
  const glm::dvec3 l = lampDirection();
  for (uint32_t y = 0; y < latLong.height; ++y)
    for (uint32_t x = 0; x < latLong.width; ++x) {
      const double theta = std::numbers::pi * (y + 0.5) / latLong.height;
      const double phi = 2 * std::numbers::pi * (x + 0.5) / latLong.width;
      const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
      const bool inLamp = glm::dot(d, l) > std::cos(6 * std::numbers::pi / 180);
      float* p = latLong.pixel(x, y);
      const float sky = 0.04f + 0.06f * float(std::max(0.0, d.z));
      p[0] = inLamp ? lamp : sky;
      p[1] = inLamp ? 0.9f * lamp : sky;
      p[2] = inLamp ? 0.7f * lamp : 1.2f * sky;
    }
  return latLong;
}

// The photograph as the webcam would store it: sRGB, 8 bits, BGR.
cv::Mat encode(const core::ImageF& linear) {
  cv::Mat bgr(int(linear.height), int(linear.width), CV_8UC3);
  for (uint32_t y = 0; y < linear.height; ++y)
    for (uint32_t x = 0; x < linear.width; ++x) {
      const float* p = linear.pixel(x, y);
      uint8_t* q = bgr.ptr<uint8_t>(int(y), int(x));
      q[0] = encodeSrgb8(p[2]), q[1] = encodeSrgb8(p[1]), q[2] = encodeSrgb8(p[0]);
    }
  return bgr;
}

struct Recording {
  std::filesystem::path dir, pattern;
  core::ImageF linear;  // the photograph before encoding
  cv::Mat bgr;
};

Recording writeSequence(const std::string& tag, float lamp, int frames) {
  Recording r;
  r.dir = test::scratchPath(tag);
  std::filesystem::remove_all(r.dir);
  std::filesystem::create_directories(r.dir);
  r.pattern = r.dir / "frame_%03d.png";
  r.linear = envmap::renderFisheye(room(lamp), envmap::FisheyeLens::equidistant180(kSize));
  r.bgr = encode(r.linear);
  for (int i = 0; i < frames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    EXPECT_TRUE(cv::imwrite((r.dir / name).string(), r.bgr));
  }
  return r;
}

kiosk::EnvironmentCameraSettings settings(const std::string& device, double exposureScale = 1) {
  kiosk::EnvironmentCameraSettings s;
  s.device = device;
  s.width = s.height = kSize;
  s.lens = envmap::FisheyeLens::equidistant180(kSize, kSize);
  s.exposureScale = exposureScale;
  return s;
}

// The luminance-weighted centre of the map's pixels brighter than half its brightest.
glm::dvec3 brightestRegion(const envmap::HemisphereMap& map) {
  float peak = 0;
  for (uint32_t r = 0; r < map.rows(); ++r)
    for (uint32_t c = 0; c < map.cols(); ++c) {
      const float* p = map.radiance.pixel(c, r);
      peak = std::max(peak, float(core::luminance(glm::dvec3(p[0], p[1], p[2]))));
    }
  glm::dvec3 sum(0);
  for (uint32_t r = 0; r < map.rows(); ++r)
    for (uint32_t c = 0; c < map.cols(); ++c) {
      const float* p = map.radiance.pixel(c, r);
      const float y = float(core::luminance(glm::dvec3(p[0], p[1], p[2])));
      if (y > peak / 2) sum += double(y) * map.pixelCentre(c, r);
    }
  return glm::normalize(sum);
}

double degreesBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180 / std::numbers::pi;
}

TEST(OpenCvEnvironmentCamera, RecordingGivesTheLampsDirectionAndTheEncodedRadiance) {
  const Recording rec = writeSequence("envcam", 0.9f, 3);
  std::vector<std::string> log;
  const auto camera = openOpenCvEnvironmentCamera(
      settings(rec.pattern.string(), 2.0),
      [&](kiosk::LogLevel, const std::string& text) { log.push_back(text); });
  EXPECT_NE(camera->describe().find("frame_%03d.png"), std::string::npos) << camera->describe();
  envmap::HemisphereMap map;
  ASSERT_EQ(camera->grab(0, map), kiosk::GrabStatus::kFrame);
  ASSERT_EQ(map.cols(), envmap::kEnvmapCols);
  ASSERT_EQ(map.rows(), envmap::kEnvmapRows);
  EXPECT_LT(degreesBetween(brightestRegion(map), lampDirection()), 2.0);

  // The linearisation inverts the encoding: the map is the resampled photograph within the
  // sRGB curve's 8-bit quantisation (half a step: at most 1.6 % of the value here), halved by
  // the exposure scale.
  const envmap::FisheyeResampler resampler(envmap::FisheyeLens::equidistant180(kSize));
  envmap::HemisphereMap ideal;
  resampler.resample(rec.linear, ideal);
  double worst = 0;
  for (size_t i = 0; i < map.radiance.pixels.size(); ++i) {
    const double want = ideal.radiance.pixels[i] / 2.0, got = map.radiance.pixels[i];
    EXPECT_NEAR(got, want, 0.017 * want + 1e-6) << i;
    worst = std::max(worst, std::abs(got - want) / want);
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  EXPECT_TRUE(log.empty()) << log.front();  // no saturation at 0.9

  // Paced at the recording's rate (21 Hz when an image sequence does not say), then looped.
  EXPECT_EQ(camera->grab(10 * kMs, map), kiosk::GrabStatus::kNoFrame);
  EXPECT_EQ(camera->grab(47 * kMs, map), kiosk::GrabStatus::kNoFrame);  // due at 47.6 ms
  EXPECT_EQ(camera->grab(48 * kMs, map), kiosk::GrabStatus::kFrame);
  EXPECT_EQ(camera->grab(96 * kMs, map), kiosk::GrabStatus::kFrame);
  EXPECT_EQ(camera->grab(143 * kMs, map), kiosk::GrabStatus::kFrame);  // frame 0 again
  EXPECT_LT(degreesBetween(brightestRegion(map), lampDirection()), 2.0);
  std::filesystem::remove_all(rec.dir);
}

TEST(OpenCvEnvironmentCamera, SaturatedLampIsCountedAndSaid) {
  const Recording rec = writeSequence("envcam-sat", 4.0f, 1);
  std::vector<std::string> log;
  const auto camera = openOpenCvEnvironmentCamera(
      settings(rec.pattern.string()),
      [&](kiosk::LogLevel, const std::string& text) { log.push_back(text); });
  envmap::HemisphereMap map;
  ASSERT_EQ(camera->grab(0, map), kiosk::GrabStatus::kFrame);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("pixels saturated"), std::string::npos) << log[0];
  EXPECT_NE(log[0].find("under-reports its power"), std::string::npos) << log[0];
  // The lamp is still where it is, but clipped: at most 1.0 however bright it was.
  EXPECT_LT(degreesBetween(brightestRegion(map), lampDirection()), 2.0);
  float peak = 0;
  for (float v : map.radiance.pixels) peak = std::max(peak, v);
  EXPECT_LE(peak, 1.0f);
  std::filesystem::remove_all(rec.dir);
}

TEST(OpenCvEnvironmentCamera, VideoFileOpensThroughTheModule) {
  const Recording rec = writeSequence("envcam-avi", 0.9f, 0);
  const std::filesystem::path file = rec.dir / "fisheye.avi";
  {
    cv::VideoWriter writer(file.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10,
                           cv::Size(int(kSize), int(kSize)));
    if (!writer.isOpened()) GTEST_SKIP() << "OpenCV cannot write MJPG .avi here";
    for (int i = 0; i < 4; ++i) writer.write(rec.bgr);
  }
  const auto camera = openOpenCvEnvironmentCamera(settings(file.string()), {});
  envmap::HemisphereMap map;
  ASSERT_EQ(camera->grab(0, map), kiosk::GrabStatus::kFrame);
  EXPECT_LT(degreesBetween(brightestRegion(map), lampDirection()), 2.0);
  // 10 fps: the next frame is due at 100 ms.
  EXPECT_EQ(camera->grab(60 * kMs, map), kiosk::GrabStatus::kNoFrame);
  EXPECT_EQ(camera->grab(100 * kMs, map), kiosk::GrabStatus::kFrame);
  EXPECT_EQ(camera->grab(300 * kMs, map), kiosk::GrabStatus::kFrame);  // frame 3, the last
  EXPECT_EQ(camera->grab(400 * kMs, map), kiosk::GrabStatus::kFrame);  // frame 0 again
  EXPECT_LT(degreesBetween(brightestRegion(map), lampDirection()), 2.0);
  std::filesystem::remove_all(rec.dir);
}

TEST(OpenCvEnvironmentCamera, MissingSourcesAreRefusedNamingThem) {
  try {
    openOpenCvEnvironmentCamera(settings("/dev/video-penumbra-absent"), {});
    FAIL();
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "environment camera: cannot open /dev/video-penumbra-absent: no such device"),
              std::string::npos)
        << e.what();
  }
  try {
    openOpenCvEnvironmentCamera(settings("/nonexistent/penumbra/fisheye.avi"), {});
    FAIL();
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("fisheye.avi: no such file"), std::string::npos)
        << e.what();
  }
  // A node that is no camera reaches the module, and V4L2's refusal comes back.
  try {
    openOpenCvEnvironmentCamera(settings("/dev/null"), {});
    FAIL();
  } catch (const HardwareUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/null: cannot be opened with V4L2"),
              std::string::npos)
        << e.what();
  }
}

// A source that goes away is kDisconnected with one message, tried again every second, and
// comes back when it does.
TEST(OpenCvEnvironmentCamera, VanishedSourceIsDisconnectedSaidAndReopened) {
  const Recording rec = writeSequence("envcam-gone", 0.9f, 2);
  std::vector<std::string> log;
  const auto camera = openOpenCvEnvironmentCamera(
      settings(rec.pattern.string()),
      [&](kiosk::LogLevel, const std::string& text) { log.push_back(text); });
  envmap::HemisphereMap map;
  ASSERT_EQ(camera->grab(0, map), kiosk::GrabStatus::kFrame);
  for (int i = 0; i < 2; ++i) {
    std::filesystem::remove(rec.dir / ("frame_00" + std::to_string(i) + ".png"));
  }
  // The recording runs dry (within a few frames, should a reader hold some it read ahead), and
  // cannot be started again.
  int64_t gone = -1;
  for (int64_t t = 48 * kMs; t < 480 * kMs && gone < 0; t += 48 * kMs) {
    if (camera->grab(t, map) == kiosk::GrabStatus::kDisconnected) gone = t;
  }
  ASSERT_GE(gone, 0) << "frames still came from a deleted recording";
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("environment camera: " + rec.pattern.string() +
                        ": no frame (the recording cannot be read); reopening every second"),
            std::string::npos)
      << log[0];
  EXPECT_EQ(camera->grab(gone + 500 * kMs, map), kiosk::GrabStatus::kDisconnected);
  EXPECT_EQ(camera->grab(gone + 1060 * kMs, map), kiosk::GrabStatus::kDisconnected);  // retried
  EXPECT_EQ(log.size(), 1u);                                                          // said once
  cv::imwrite((rec.dir / "frame_000.png").string(), rec.bgr);
  EXPECT_EQ(camera->grab(gone + 1500 * kMs, map), kiosk::GrabStatus::kDisconnected);  // not yet
  EXPECT_EQ(camera->grab(gone + 2100 * kMs, map), kiosk::GrabStatus::kFrame);
  ASSERT_EQ(log.size(), 2u);
  EXPECT_NE(log[1].find("open again"), std::string::npos) << log[1];
  EXPECT_LT(degreesBetween(brightestRegion(map), lampDirection()), 2.0);
  std::filesystem::remove_all(rec.dir);
}

TEST(OpenCvEnvironmentCamera, FramesOfAnotherSizeAreRefused) {
  const Recording rec = writeSequence("envcam-size", 0.9f, 1);
  kiosk::EnvironmentCameraSettings s = settings(rec.pattern.string());
  s.width = s.height = 200;
  s.lens = envmap::FisheyeLens::equidistant180(200, 200);
  const auto camera = openOpenCvEnvironmentCamera(s, {});
  envmap::HemisphereMap map;
  try {
    camera->grab(0, map);
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 0: 240x240, the lens is for 200x200"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(rec.dir);
}

}  // namespace
}  // namespace penumbra::platform
#endif
