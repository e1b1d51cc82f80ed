// The calibrated response file (kiosk/camera_response_file.h): it reads back bit for bit, and
// every way a file can be wrong is refused naming the file, the field and the problem.
#include "kiosk/camera_response_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "tests/scratch_dir.h"

namespace penumbra::kiosk {
namespace {

std::filesystem::path scratch() {
  const std::filesystem::path dir = test::scratchPath("camera-response-file");
  std::filesystem::create_directories(dir);
  return dir;
}

// An S-shaped log response per channel with values that need all 17 digits.
CameraResponseCurves sCurves() {
  CameraResponseCurves curves;
  for (size_t c = 0; c < 3; ++c)
    for (size_t z = 0; z < 256; ++z) {
      const double t = (double(z) - 127.5) / 127.5;
      curves.logExposure[c][z] = 4.0 * t + std::sin(3.0 * t) / (7.0 + double(c));
    }
  curves.bracket = {{"e \"250\".png", 250}, {"e2000.png", 2000}};
  curves.warnings = {"channel R: response not monotone at 1 code(s), first at 3"};
  return curves;
}

std::string valid(const std::string& r) {
  std::string numbers;
  for (int z = 0; z < 256; ++z) numbers += (z ? ", " : "") + std::to_string((z - 128) / 4.0);
  return R"({"format": "penumbra-camera-response", "version": 1, "log_exposure": {"r": )" + r +
         ", \"g\": [" + numbers + "], \"b\": [" + numbers + "]}}";
}

TEST(CameraResponseFile, ReadsBackBitForBit) {
  const std::filesystem::path file = scratch() / "response.json";
  const CameraResponseCurves curves = sCurves();
  ASSERT_TRUE(checkLogExposure(curves.logExposure).empty()) << checkLogExposure(curves.logExposure);
  writeCameraResponse(file, curves);
  const CameraResponseCurves back = readCameraResponse(file, core::throwAs<core::Error>);
  EXPECT_EQ(back.logExposure, curves.logExposure);  // every double, exactly
  ASSERT_EQ(back.bracket.size(), 2u);
  EXPECT_EQ(back.bracket[0].image, "e \"250\".png");
  EXPECT_EQ(back.bracket[1].exposureUs, 2000);
  EXPECT_EQ(back.warnings, curves.warnings);
}

TEST(CameraResponseFile, CurvesThatCannotBeUsedAreNamed) {
  CameraResponseCurves c = sCurves();
  c.logExposure[1][17] = c.logExposure[1][16] - 0.5;
  EXPECT_NE(checkLogExposure(c.logExposure).find("channel G: g(17) = "), std::string::npos);
  EXPECT_NE(checkLogExposure(c.logExposure).find("is below g(16)"), std::string::npos);
  c = sCurves();
  c.logExposure[2][3] = NAN;
  EXPECT_EQ(checkLogExposure(c.logExposure), "channel B: g(3) is not finite");
  c = sCurves();
  c.logExposure[0][255] = 61;
  EXPECT_EQ(checkLogExposure(c.logExposure), "channel R: g(255) = 61 is beyond ±60");
  c = sCurves();
  c.logExposure[0].fill(0);
  EXPECT_EQ(checkLogExposure(c.logExposure),
            "channel R: g is flat (it records no change of light)");
  // The writer refuses them too, naming the file; nothing is written.
  const std::filesystem::path file = scratch() / "flat.json";
  try {
    writeCameraResponse(file, c);
    ADD_FAILURE() << "wrote a flat response";
  } catch (const core::Error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ": channel R: g is flat (it records no change of light)");
  }
  EXPECT_FALSE(std::filesystem::exists(file));
}

TEST(CameraResponseFile, BadFilesAreRefusedNamingFileAndField) {
  std::string decreasing = "[";
  for (int z = 0; z < 256; ++z)
    decreasing += (z ? ", " : "") + std::to_string(z == 200 ? 0 : z / 4.0);
  decreasing += "]";
  std::string huge = "[1e400";
  for (int z = 1; z < 256; ++z) huge += ", " + std::to_string(z / 4.0);
  huge += "]";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"not json", "line 1"},
      {"[1, 2]", "expected an object"},
      {R"({"format": "penumbra-trace", "version": 1, "log_exposure": {}})",
       "format: expected \"penumbra-camera-response\" (a file written by `penumbra "
       "camera-response`), got \"penumbra-trace\""},
      {R"({"version": 1, "log_exposure": {}})", "format: missing"},
      {R"({"format": "penumbra-camera-response", "version": 2, "log_exposure": {}})",
       "version: 2 is not in [1, 1]"},
      {R"({"format": "penumbra-camera-response", "version": 1, "log_exposure": {"r": []}})",
       "log_exposure.r: expected an array of 256 numbers, got an array of 0"},
      {R"({"format": "penumbra-camera-response", "version": 1,
           "log_exposure": {"r": [], "g": [], "b": [], "a": []}})",
       "log_exposure.a: unknown field"},
      {valid(decreasing),
       "log_exposure: channel R: g(200) = 0 is below g(199) = 49.75 (a response must not "
       "decrease)"},
      {valid(huge), "log_exposure.r[0]: expected a number within double's range"},
      {R"({"format": "penumbra-camera-response", "version": 1, "log_exposure": {"r": [], "g": [], "b": []},
           "gamma": 2.2})",
       "gamma: unknown field"},
  };
  int i = 0;
  for (const auto& [text, expected] : cases) {
    const std::filesystem::path file = scratch() / ("bad-" + std::to_string(i++) + ".json");
    std::ofstream(file) << text;
    try {
      readCameraResponse(file, core::throwAs<core::Error>);
      ADD_FAILURE() << "accepted " << text;
    } catch (const core::Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  }
  // A valid file of the same shape is read (the cases fail for their stated reason).
  std::string increasing = "[";
  for (int z = 0; z < 256; ++z) increasing += (z ? ", " : "") + std::to_string(z / 8.0);
  const std::filesystem::path file = scratch() / "good.json";
  std::ofstream(file) << valid(increasing + "]");
  EXPECT_EQ(readCameraResponse(file, core::throwAs<core::Error>).logExposure[0][200], 25.0);
}

}  // namespace
}  // namespace penumbra::kiosk
