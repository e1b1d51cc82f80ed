#include "lighting/exr_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "lighting/camera_response.h"
#include "lighting/hdr_merge.h"
#include "lighting/hdr_test_util.h"
#include "tests/scratch_dir.h"
#include "tests/test_data.h"

namespace penumbra::lighting {
namespace {

class ExrFiles : public ::testing::Test {
 protected:
  std::filesystem::path dir = test::scratchPath("exr");
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
};

// Real data nobody here made: Blender's eight CC0 lat-long studio-light probes, DWAB
// compressed, with small negative values from the lossy compression.
TEST_F(ExrFiles, ReadsEveryBlenderProbeAndClampsNegatives) {
  if (!std::filesystem::exists(penumbra::testing::blenderProbeDir()))
    GTEST_SKIP() << "blender-data is not installed";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(penumbra::testing::blenderProbeDir())) {
    if (e.path().extension() == ".exr") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_EQ(files.size(), 8u);
  size_t totalClamped = 0;
  for (const auto& f : files) {
    ExrReadReport report;
    const core::ImageF img = readExr(f, &report);
    EXPECT_GT(img.width, 0);
    EXPECT_EQ(img.width, 2 * img.height) << f << " is not lat-long";
    EXPECT_EQ(img.pixels.size(), size_t(img.width) * img.height * 3);
    float maxV = 0;
    for (float v : img.pixels) {
      ASSERT_GE(v, 0.0f);
      maxV = std::max(maxV, v);
    }
    EXPECT_GT(maxV, 0.0f);
    EXPECT_LE(report.mostNegative, 0.0f);
    EXPECT_EQ(report.clampedNegative == 0, report.mostNegative == 0.0f);
    std::printf("%s: %ux%u, max %.3g, clamped %zu negative values (most negative %.3g)\n",
                f.filename().c_str(), img.width, img.height, double(maxV), report.clampedNegative,
                double(report.mostNegative));
    totalClamped += report.clampedNegative;
  }
  EXPECT_GT(totalClamped, 0u);  // the DWAB ringing is really there
}

TEST_F(ExrFiles, WriteReadRoundTripIsExact) {
  const core::ImageF img = testutil::gradientField(37, 23);
  writeExr(dir / "g.exr", img);
  ExrReadReport report;
  const core::ImageF back = readExr(dir / "g.exr", &report);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.pixels, img.pixels);
  EXPECT_EQ(report.clampedNegative, 0u);
}

// Half: values a half holds exactly come back exactly, others within half an ulp of binary16
// (2⁻¹¹ relative), at about half the bytes; beyond 65504 refused (it would be infinite).
TEST_F(ExrFiles, HalfRoundTripIsTheNearestHalf) {
  core::ImageF img(40, 30);
  for (size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = i % 2 == 0 ? float(i % 997) / 64.0f : float(i) / 3.0f;
  writeExr(dir / "half.exr", img, ExrPixels::Half);
  writeExr(dir / "float.exr", img);
  const core::ImageF back = readExr(dir / "half.exr");
  ASSERT_EQ(back.pixels.size(), img.pixels.size());
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    if (i % 2 == 0)
      EXPECT_EQ(back.pixels[i], img.pixels[i]) << i;
    else
      EXPECT_NEAR(back.pixels[i], img.pixels[i], img.pixels[i] / 2048.0f) << i;
  }
  EXPECT_LT(std::filesystem::file_size(dir / "half.exr"),
            std::filesystem::file_size(dir / "float.exr"));
  img.pixels[7] = 70000.0f;
  try {
    writeExr(dir / "bright.exr", img, ExrPixels::Half);
    FAIL();
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find("bright.exr: value 70000"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "bright.exr"));
  EXPECT_NO_THROW(writeExr(dir / "bright.exr", img));  // float holds it
}

TEST_F(ExrFiles, BadFilesAndImagesNamed) {
  try {
    readExr(dir / "missing.exr");
    FAIL();
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
  }
  std::ofstream(dir / "garbage.exr") << "not an exr file at all";
  try {
    readExr(dir / "garbage.exr");
    FAIL();
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.exr"), std::string::npos) << e.what();
  }
  core::ImageF img = testutil::gradientField(8, 8);
  img.pixels[5] = std::nanf("");
  EXPECT_THROW(writeExr(dir / "nan.exr", img), HdrError);
  EXPECT_FALSE(std::filesystem::exists(dir / "nan.exr"));
  img.pixels.resize(10);
  EXPECT_THROW(writeExr(dir / "short.exr", img), HdrError);
  // A header that announces more pixels than the limit is refused before any allocation:
  // an 8x6 file's data window rewritten in place to 6,000,000 x 6 (36 Mpx; the same six
  // lines, so OpenEXR's line-offset table still reads).
  writeExr(dir / "window.exr", testutil::gradientField(8, 6));
  std::string bytes;
  {
    std::ifstream in(dir / "window.exr", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string key("dataWindow\0box2i\0", 17);
  const size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const int32_t box[4] = {0, 0, 5'999'999, 5};  // xMin yMin xMax yMax, after the 4-byte size
  std::memcpy(bytes.data() + at + key.size() + 4, box, sizeof box);
  std::ofstream(dir / "window.exr", std::ios::binary) << bytes;
  try {
    readExr(dir / "window.exr");
    FAIL();
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "window.exr: data window of 6000000x6 pixels: expected 1 to 33554432 pixels"),
              std::string::npos)
        << e.what();
  }
  // Large but finite values pass through.
  img = testutil::gradientField(8, 8);
  img.pixels[4] = 1e30f;
  writeExr(dir / "big.exr", img);
  EXPECT_NO_THROW(readExr(dir / "big.exr"));
}

// The response recovery and merge on real radiance: a Blender probe pushed through a known
// response at five exposures, then recovered.
TEST_F(ExrFiles, ProbeBracketRecoversResponseAndRadiance) {
  const auto probe = penumbra::testing::blenderProbeDir() / "interior.exr";
  if (!std::filesystem::exists(probe)) GTEST_SKIP() << "blender-data is not installed";
  core::ImageF truth = readExr(probe);
  // Scale so the median channel value sits mid-range at dt = 1, and lift exact zeros (a
  // zero radiance is clipped in every exposure and has no relative error).
  std::vector<float> sorted = truth.pixels;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const float scale = 0.2f / sorted[sorted.size() / 2];
  for (float& v : truth.pixels) v = std::max(v * scale, 1e-4f);
  const double times[5] = {1.0 / 16, 1.0 / 4, 1.0, 4.0, 16.0};
  const auto bracket = testutil::makeBracket(truth, times);
  const CameraResponse r = recoverResponse(bracket);
  for (int c = 0; c < 3; ++c) {
    const double offset = r.logExposure[c][128] - testutil::trueLogExposure(c, 128);
    double worst = 0;
    for (int z = 16; z <= 250; ++z) {
      worst =
          std::max(worst, std::abs(r.logExposure[c][z] - offset - testutil::trueLogExposure(c, z)));
    }
    std::printf("probe bracket, channel %d: max |ln error| codes 16..250 = %.4f\n", c, worst);
    EXPECT_LT(worst, 0.03);  // measured <= 0.013
  }
  const MergeResult m = mergeExposures(bracket, r);
  // Relative error over channel values that some exposure measured (not clipped throughout).
  std::vector<uint8_t> measured(truth.pixels.size(), 0);
  for (size_t i = 0; i < truth.pixels.size(); ++i) {
    for (const Exposure& e : bracket) {
      if (hatWeight(e.image.pixels[i]) > 0) measured[i] = 1;
    }
  }
  const std::vector<double> err = testutil::relativeErrors(m.radiance, truth, measured);
  const double p50 = testutil::quantile(err, 0.5), p99 = testutil::quantile(err, 0.99);
  std::printf(
      "probe merge: %zu values, relative error median %.4f p99 %.4f; clipped bright %zu "
      "dark %zu\n",
      err.size(), p50, p99, m.clippedBright, m.clippedDark);
  EXPECT_LT(p50, 0.01);
  EXPECT_LT(p99, 0.05);
}

}  // namespace
}  // namespace penumbra::lighting
