#include "reference/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

namespace penumbra::reference {
namespace {

core::Image8 uniform(uint32_t w, uint32_t h, uint8_t v, const char* name = "uniform") {
  return core::Image8(w, h, 3, name, v);
}

TEST(ImageMetrics, ImageAgainstItselfIsPerfect) {
  core::Image8 a = uniform(16, 12, 0);
  for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = uint8_t((i * 37) % 251);
  const ImageComparison c = compareImages(a, a);
  EXPECT_EQ(c.frame.pixels, 16u * 12u);
  EXPECT_EQ(c.frame.meanAbs, 0.0);
  EXPECT_EQ(c.frame.p99Abs, 0u);
  EXPECT_EQ(c.frame.maxAbs, 0u);
  EXPECT_TRUE(std::isinf(c.frame.psnr));
  EXPECT_DOUBLE_EQ(c.ssim, 1.0);
  EXPECT_EQ(c.frame.flipMean, 0.0);
  for (float f : c.flipMap) ASSERT_EQ(f, 0.0f);
  const nlohmann::json j = toJson(c);
  EXPECT_TRUE(j["frame"]["psnr"].is_null());
  EXPECT_TRUE(j["frame"]["identical"].get<bool>());
  EXPECT_EQ(j["frame"]["mean_abs"].get<double>(), 0.0);
}

// 4×4 grey 100; pixel (0,0) red +10, pixel (1,0) all channels −3. 48 samples: one 10, three
// 3, the rest 0. mean = 19/48, max = 10, nearest-rank p99 = the 48th smallest (⌈47.52⌉) = 10,
// MSE = (100 + 27)/48, PSNR = 10·log10(65025·48/127) = 43.90518.
TEST(ImageMetrics, MatchesHandComputedValuesOn4x4) {
  const core::Image8 a = uniform(4, 4, 100, "a");
  core::Image8 b = uniform(4, 4, 100, "b");
  b.pixels[0] = 110;
  for (int k = 0; k < 3; ++k) b.pixels[size_t(3 + k)] = 97;
  core::Image8 m(4, 4, 1, "mask");
  m.pixels[0] = 255;  // only pixel (0,0) inside: samples 10, 0, 0
  m.pixels[5] = 1;    // and pixel (1,1), unchanged
  CompareOptions o;
  o.computeFlip = false;
  const ImageComparison c = compareImages(a, b, &m, o);
  EXPECT_DOUBLE_EQ(c.frame.meanAbs, 19.0 / 48.0);
  EXPECT_EQ(c.frame.maxAbs, 10u);
  EXPECT_EQ(c.frame.p99Abs, 10u);
  EXPECT_NEAR(c.frame.psnr, 43.90518, 1e-4);
  ASSERT_TRUE(c.masked.has_value());
  EXPECT_EQ(c.masked->pixels, 2u);
  EXPECT_DOUBLE_EQ(c.masked->meanAbs, 10.0 / 6.0);
  EXPECT_EQ(c.masked->maxAbs, 10u);
  EXPECT_NEAR(c.masked->psnr, 10.0 * std::log10(65025.0 * 6.0 / 100.0), 1e-9);
  EXPECT_LT(c.ssim, 1.0);
  ASSERT_TRUE(c.ssimMasked.has_value());
  EXPECT_TRUE(toJson(c)["frame"]["flip_mean"].is_null());
}

// Nearest rank over 300 samples: rank ⌈297⌉ = 297. Errors sorted: 295 zeros, 20, 20, 50, 50,
// 50 → the 297th is 20 (a mean of the top 1% or an interpolated percentile would differ).
TEST(ImageMetrics, P99IsNearestRankOverChannelSamples) {
  const core::Image8 a = uniform(10, 10, 128, "a");
  core::Image8 b = a;
  b.pixels[0] = 178;
  b.pixels[10] = 78;
  b.pixels[299] = 178;
  b.pixels[50] = 148;
  b.pixels[51] = 108;
  CompareOptions o;
  o.computeFlip = false;
  const ImageComparison c = compareImages(a, b, nullptr, o);
  EXPECT_EQ(c.frame.p99Abs, 20u);
  EXPECT_EQ(c.frame.maxAbs, 50u);
  EXPECT_DOUBLE_EQ(c.frame.meanAbs, 190.0 / 300.0);
}

TEST(ImageMetrics, EmptyMaskGivesNullRegion) {
  const core::Image8 a = uniform(8, 8, 10, "a");
  const core::Image8 b = uniform(8, 8, 20, "b");
  const core::Image8 m(8, 8, 1, "empty.png");
  const ImageComparison c = compareImages(a, b, &m);
  EXPECT_EQ(c.masked->pixels, 0u);
  EXPECT_FALSE(c.ssimMasked.has_value());
  const nlohmann::json j = toJson(c);
  EXPECT_TRUE(j["mask"]["mean_abs"].is_null());
  EXPECT_TRUE(j["ssim_mask"].is_null());
  EXPECT_DOUBLE_EQ(j["frame"]["mean_abs"].get<double>(), 10.0);
}

TEST(ImageMetrics, SsimFallsWithNoise) {
  core::Image8 a = uniform(32, 32, 0, "a");
  for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = uint8_t(64 + (i / 3) % 128);
  core::Image8 small = a, large = a;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    const int n = int((i * 2654435761u) >> 28) - 8;  // −8..7, fixed pattern
    small.pixels[i] = uint8_t(int(a.pixels[i]) + n / 4);
    large.pixels[i] = uint8_t(int(a.pixels[i]) + 4 * n);
  }
  const double s1 = compareImages(a, small).ssim, s2 = compareImages(a, large).ssim;
  EXPECT_LT(s1, 1.0);
  EXPECT_LT(s2, s1);
  EXPECT_GT(s2, 0.0);
}

// Expects `f` to throw MetricsError whose message contains every one of `needles`.
template <class F>
void expectError(F f, std::initializer_list<std::string> needles) {
  try {
    f();
    ADD_FAILURE() << "no MetricsError";
  } catch (const MetricsError& e) {
    for (const std::string& n : needles) {
      EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what() << " lacks " << n;
    }
  }
}

// Against bounds: a sample inside [lower, upper] has no error, one outside has its distance
// to the nearer end; outside the mask nothing counts; bounds the wrong way round are refused.
TEST(ImageMetrics, IntervalErrorsCountOnlyWhatLiesOutsideTheBounds) {
  const core::Image8 lower = uniform(2, 2, 10, "lower"), upper = uniform(2, 2, 20, "upper");
  core::Image8 test = uniform(2, 2, 15, "test");
  test.pixels[0] = 4;   // 6 below
  test.pixels[4] = 23;  // 3 above
  test.pixels[11] = 0;  // outside the mask
  core::Image8 mask(2, 2, 1, "mask", 255);
  mask.pixels[3] = 0;
  const RegionErrors r = intervalErrors(lower, upper, test, mask);
  EXPECT_EQ(r.pixels, 3u);
  EXPECT_DOUBLE_EQ(r.meanAbs, 9.0 / 9.0);
  EXPECT_EQ(r.maxAbs, 6u);
  EXPECT_EQ(r.p99Abs, 6u);
  core::Image8 swapped = lower;
  swapped.pixels[5] = 30;
  EXPECT_THROW(intervalErrors(swapped, upper, test, mask), MetricsError);
  EXPECT_THROW(intervalErrors(lower, uniform(2, 1, 20, "short"), test, mask), MetricsError);
}

TEST(ImageMetrics, MismatchedSizesNameTheFiles) {
  const core::Image8 a = uniform(4, 4, 0, "ref.png");
  const core::Image8 b = uniform(4, 5, 0, "test.png");
  expectError([&] { compareImages(a, b); }, {"test.png", "ref.png", "4x5", "4x4"});
  const core::Image8 m(3, 4, 1, "shadow-mask.png", 1);
  expectError([&] { compareImages(a, a, &m); }, {"shadow-mask.png", "3x4"});
}

class ImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() /
        ("penumbra_metrics_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(ImageFiles, LoadsRgbInRgbOrderAndMasks) {
  cv::Mat bgra(2, 3, CV_8UC4, cv::Scalar(30, 20, 10, 128));  // B, G, R, A
  ASSERT_TRUE(cv::imwrite((dir_ / "a.png").string(), bgra));
  const core::Image8 img = loadRgb8(dir_ / "a.png");
  EXPECT_EQ(img.width, 3u);
  EXPECT_EQ(img.height, 2u);
  EXPECT_EQ(img.pixels[0], 10);
  EXPECT_EQ(img.pixels[1], 20);
  EXPECT_EQ(img.pixels[2], 30);
  cv::Mat mask(2, 3, CV_8UC1, cv::Scalar(0));
  mask.at<uint8_t>(1, 2) = 7;
  ASSERT_TRUE(cv::imwrite((dir_ / "m.png").string(), mask));
  const core::Image8 m = loadMask(dir_ / "m.png");
  EXPECT_EQ(m.channels, 1u);
  ASSERT_EQ(m.pixels.size(), 6u);
  EXPECT_EQ(m.pixels[5], 7);
  EXPECT_EQ(m.pixels[0], 0);
}

TEST_F(ImageFiles, UnreadableFilesAreNamed) {
  expectError([&] { loadRgb8(dir_ / "missing.png"); }, {"missing.png", "not found"});
  std::ofstream(dir_ / "garbage.png") << "not a png at all";
  expectError([&] { loadRgb8(dir_ / "garbage.png"); }, {"garbage.png", "cannot decode"});
  expectError([&] { loadMask(dir_ / "garbage.png"); }, {"garbage.png", "mask"});
  expectError(
      [&] { writeHeatmapPng(dir_ / "no-such-dir" / "h.png", std::vector<float>(4, 0.f), 2, 2); },
      {"h.png"});
}

TEST(Heatmap, ColourMapEndsAndOrder) {
  EXPECT_EQ(heatmapColour(0.0f), (std::array<uint8_t, 3>{0, 0, 4}));
  EXPECT_EQ(heatmapColour(1.0f), (std::array<uint8_t, 3>{252, 253, 191}));
  EXPECT_EQ(heatmapColour(-3.0f), heatmapColour(0.0f));
  EXPECT_EQ(heatmapColour(7.0f), heatmapColour(1.0f));
  // Brightness (sum of channels) grows with the value: the map reads in greyscale.
  int last = -1;
  for (int i = 0; i <= 64; ++i) {
    const auto c = heatmapColour(float(i) / 64.0f);
    const int sum = c[0] + c[1] + c[2];
    EXPECT_GT(sum, last) << i;
    last = sum;
  }
}

}  // namespace
}  // namespace penumbra::reference
