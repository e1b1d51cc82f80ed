#include "lighting/hdr_merge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "lighting/hdr_test_util.h"

namespace penumbra::lighting {
namespace {

using testutil::gradientField;
using testutil::kBracketTimes;
using testutil::makeBracket;

TEST(HdrMerge, RecoversRadianceOfASyntheticBracket) {
  const core::ImageF truth = gradientField(320, 240);
  const auto bracket = makeBracket(truth, kBracketTimes);
  const MergeResult m = mergeExposures(bracket, recoverResponse(bracket));
  ASSERT_EQ(m.radiance.width, 320);
  EXPECT_EQ(m.clippedBright, 0u);
  EXPECT_EQ(m.clippedDark, 0u);
  const std::vector<double> err = testutil::relativeErrors(m.radiance, truth);
  const double p50 = testutil::quantile(err, 0.5), p99 = testutil::quantile(err, 0.99);
  std::printf("merge relative error: median %.4f, 99th percentile %.4f\n", p50, p99);
  EXPECT_LT(p50, 0.01);
  EXPECT_LT(p99, 0.03);
  EXPECT_GT(m.maxRadiance / m.minRadiance, 1000.0);
}

TEST(HdrMerge, ClippedCodesCarryNoWeight) {
  const core::ImageF truth = gradientField(64, 48);
  auto bracket = makeBracket(truth, kBracketTimes);
  const CameraResponse r = recoverResponse(bracket);
  const MergeResult before = mergeExposures(bracket, r);
  // Pixel 0 (the darkest corner): clip it to 255 in the longest exposure only. With a hat
  // weight of 0 at 255 the estimate must not move (OpenCV's MergeDebevec would pull it).
  const size_t p = 5;  // a dark pixel, below 255 in every exposure
  ASSERT_LT(bracket[4].image.pixels[3 * p], 250);
  bracket[4].image.pixels[3 * p] = 255;
  const MergeResult after = mergeExposures(bracket, r);
  const double withoutLongest = [&] {
    double num = 0, den = 0;
    for (size_t j = 0; j < 4; ++j) {
      const int z = bracket[j].image.pixels[3 * p];
      num += hatWeight(z) * (r.logExposure[0][z] - std::log(kBracketTimes[j]));
      den += hatWeight(z);
    }
    return std::exp(num / den);
  }();
  EXPECT_FLOAT_EQ(after.radiance.pixels[3 * p], float(withoutLongest));
  EXPECT_NE(after.radiance.pixels[3 * p], before.radiance.pixels[3 * p]);
  // A pixel saturated in every exposure is counted and gets the brightest measurable value.
  for (Exposure& e : bracket) e.image.pixels[3 * 7 + 1] = 255;
  for (Exposure& e : bracket) e.image.pixels[3 * 9 + 2] = 0;
  const MergeResult clipped = mergeExposures(bracket, r);
  EXPECT_EQ(clipped.clippedBright, before.clippedBright + 1);
  EXPECT_EQ(clipped.clippedDark, before.clippedDark + 1);
  EXPECT_FLOAT_EQ(clipped.radiance.pixels[3 * 7 + 1],
                  float(std::exp(r.logExposure[1][254] - std::log(kBracketTimes[0]))));
}

TEST(HdrMerge, InvalidBracketsRejected) {
  auto bracket = makeBracket(gradientField(32, 24), kBracketTimes);
  const CameraResponse r = recoverResponse(bracket);
  EXPECT_THROW(mergeExposures(std::span(bracket).first(1), r), HdrError);
  bracket[1].image.height = 12;
  bracket[1].image.pixels.resize(32 * 12 * 3);
  try {
    mergeExposures(bracket, r);
    FAIL();
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find("differs from the first"), std::string::npos);
  }
}

}  // namespace
}  // namespace penumbra::lighting
