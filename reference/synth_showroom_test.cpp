#ifdef PENUMBRA_HAVE_SYNTH_SHOWROOM
#include "reference/synth_showroom.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "lighting/exr_io.h"
#include "scene/vanishing_points.h"
#include "tests/test_data.h"

namespace penumbra::reference {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

SynthOptions smallOptions() {
  SynthOptions o;
  o.width = 160;
  o.height = 120;
  o.render.samplesPerPixel = 1;
  o.render.lightSamples = 2;
  o.render.bounces = 1;
  o.probeSize = 24;
  return o;
}

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("penumbra_synth_" + name);
  fs::remove_all(dir);
  return dir;
}

TEST(SynthShowroom, WritesACaptureManifestWhoseMarksGiveTheTrueCameraBack) {
  const scene::SceneDescription sc =
      scene::loadSceneFile(testing::dataDir() / "showroom" / "showroom.json");
  SynthOptions o = smallOptions();
  o.render.threads = 1;
  const fs::path one = freshDir("t1");
  writeSynthShowroom(sc, o, one);
  o.render.threads = 3;
  const fs::path three = freshDir("t3");
  writeSynthShowroom(sc, o, three);

  // Every file, byte for byte, for any thread count.
  size_t files = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(one)) {
    ++files;
    EXPECT_EQ(slurp(e.path()), slurp(three / e.path().filename())) << e.path().filename();
  }
  EXPECT_GE(files, 14u);

  // The manifest is docs/capture.md's format and names files that exist.
  const nlohmann::json m = nlohmann::json::parse(slurp(one / "capture.json"));
  EXPECT_EQ(m["format"], "penumbra-capture");
  EXPECT_EQ(m["version"], 1);
  ASSERT_EQ(m["exposures"].size(), 5u);
  double previous = 0;
  for (const nlohmann::json& e : m["exposures"]) {
    EXPECT_TRUE(fs::exists(one / e["image"].get<std::string>()));
    EXPECT_GT(e["seconds"].get<double>(), previous);
    previous = e["seconds"].get<double>();
  }
  EXPECT_EQ(m["live_exposure"]["index"], 2);
  EXPECT_EQ(m["probe"]["mapping"], "mirror_ball");
  EXPECT_TRUE(fs::exists(one / m["probe"]["image"].get<std::string>()));

  // The object-present radiance differs from the empty room's: the product is in view
  // and casts shadows (one render, shared samples, so elsewhere they mostly agree).
  const core::ImageF room = lighting::readExr(one / "room.exr");
  const core::ImageF present = lighting::readExr(one / "object_present.exr");
  ASSERT_EQ(room.pixels.size(), size_t{160} * 120 * 3);
  size_t differing = 0;
  for (size_t i = 0; i < room.pixels.size(); ++i) differing += room.pixels[i] != present.pixels[i];
  EXPECT_GT(differing, 300u);

  // Closed loop on the marks: vanishing-point calibration recovers the scene's camera.
  const scene::VanishingCalibration cal =
      scene::calibrateFromVanishingPoints(scene::loadVanishingMarks(one / "marks.json"));
  const double f = 0.5 * 120 / std::tan(0.5 * sc.camera.fovYDegrees * std::numbers::pi / 180);
  EXPECT_NEAR(cal.intrinsics.fx, f, 1e-6 * f);
  const nlohmann::json& ow = m["calibration"]["origin_world"];
  const glm::dvec3 eye =
      cal.pose.centre() + glm::dvec3(ow[0].get<double>(), ow[1].get<double>(), ow[2].get<double>());
  EXPECT_LT(glm::length(eye - sc.camera.eye), 1e-6);
  EXPECT_LT(cal.rmsPx, 1e-6);
}

TEST(SynthShowroom, TheResponseIsMonotoneAndItsInverseLandsInsideEachCode) {
  const CameraResponse r;
  uint8_t previous = 0;
  for (double e = 1e-4; e < 1e3; e *= 1.01) {
    const uint8_t code = r(e);
    EXPECT_GE(code, previous);
    previous = code;
  }
  EXPECT_EQ(previous, 255);
  for (int k = 1; k < 255; ++k) EXPECT_EQ(r(r.inverse(k)), k) << k;
}

TEST(SynthShowroom, RejectsBadOptions) {
  const scene::SceneDescription sc =
      scene::loadSceneFile(testing::dataDir() / "showroom" / "showroom.json");
  SynthOptions o = smallOptions();
  o.exposures = 4;
  EXPECT_THROW(writeSynthShowroom(sc, o, freshDir("bad")), std::invalid_argument);
  o = smallOptions();
  o.probePosition = {100, 1, 1};
  EXPECT_THROW(writeSynthShowroom(sc, o, freshDir("bad")), std::invalid_argument);
  o = smallOptions();
  o.pose = shadow::ProductPose{99, 1, 1, 0, 0};
  EXPECT_THROW(writeSynthShowroom(sc, o, freshDir("bad")), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
#endif
