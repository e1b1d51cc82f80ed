#include "lighting/camera_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "lighting/hdr_test_util.h"

namespace penumbra::lighting {
namespace {

using testutil::gradientField;
using testutil::kBracketTimes;
using testutil::makeBracket;
using testutil::trueLogExposure;

// Largest |recovered g - true g| over codes [lo, hi], after removing the free constant at
// code 128 (both curves are only defined up to it).
double maxLogError(const CameraResponse& r, int c, int lo, int hi) {
  const double offset = r.logExposure[c][128] - trueLogExposure(c, 128);
  double worst = 0;
  for (int z = lo; z <= hi; ++z) {
    worst = std::max(worst, std::abs(r.logExposure[c][z] - offset - trueLogExposure(c, z)));
  }
  return worst;
}

TEST(CameraResponse, RecoversAKnownCurvePerChannel) {
  const auto bracket = makeBracket(gradientField(320, 240), kBracketTimes);
  const CameraResponse r = recoverResponse(bracket);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.logExposure[c][128], 0.0, 1e-9);  // the anchor
    // Codes 16..250: within 0.03 in ln (3% in radiance; measured <= 0.018). Below 16 the 8-bit
    // quantisation of a gamma curve alone spans more than that per code.
    const double err = maxLogError(r, c, 16, 250);
    std::printf("channel %d: max |ln error| over codes 16..250 = %.4f\n", c, err);
    EXPECT_LT(err, 0.03) << "channel " << c;
    EXPECT_EQ(r.repairedCodes[c], 0);
    const std::vector<ToneSample> t = r.toneSamples(c);
    ASSERT_EQ(t.size(), 256u);
    for (int z = 1; z < 256; ++z) EXPECT_GE(t[z].radiance, t[z - 1].radiance);
  }
  EXPECT_TRUE(r.warnings.empty());
  const std::vector<ToneSample> grey = r.greyToneSamples();
  EXPECT_NEAR(std::log(grey[200].radiance),
              (r.logExposure[0][200] + r.logExposure[1][200] + r.logExposure[2][200]) / 3, 1e-12);
}

TEST(CameraResponse, IsDeterministicAndSeeded) {
  const auto bracket = makeBracket(gradientField(160, 120), kBracketTimes);
  const CameraResponse a = recoverResponse(bracket), b = recoverResponse(bracket);
  EXPECT_EQ(a.logExposure, b.logExposure);  // bit for bit
  ResponseOptions other;
  other.seed = 7;
  const CameraResponse c = recoverResponse(bracket, other);
  EXPECT_NE(a.logExposure, c.logExposure);
  EXPECT_LT(maxLogError(c, 1, 16, 250), 0.05);
}

TEST(CameraResponse, WrongExposureOrderIsNotMonotone) {
  // Exposure times given in reverse: the data say brighter codes mean less light.
  auto bracket = makeBracket(gradientField(160, 120), kBracketTimes);
  for (size_t j = 0; j < bracket.size(); ++j) bracket[j].seconds = kBracketTimes[4 - j];
  try {
    recoverResponse(bracket);
    FAIL() << "a reversed bracket gave a response";
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find("not monotone"), std::string::npos) << e.what();
  }
}

TEST(CameraResponse, SmallNonMonotonicityIsRepairedWithAWarning) {
  // A camera whose codes 100..109 come out in reverse order: the recovered g dips there.
  auto bracket = makeBracket(gradientField(160, 120), kBracketTimes);
  for (Exposure& e : bracket) {
    for (uint8_t& v : e.image.pixels) {
      if (v >= 100 && v <= 109) v = uint8_t(209 - v);
    }
  }
  const CameraResponse r = recoverResponse(bracket);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("flattened to the running maximum"), std::string::npos)
      << r.warnings[0];
  for (int c = 0; c < 3; ++c) {
    EXPECT_GE(r.repairedCodes[c], 1) << c;
    EXPECT_LE(r.repairedCodes[c], 25) << c;  // the dip plus the codes until g climbs back
    for (int z = 1; z < 256; ++z) EXPECT_GE(r.logExposure[c][z], r.logExposure[c][z - 1]);
  }
}

TEST(CameraResponse, InvalidBracketsRejected) {
  auto bracket = makeBracket(gradientField(32, 24), kBracketTimes);
  EXPECT_THROW(recoverResponse(std::span(bracket).first(1)), HdrError);
  auto dup = bracket;
  dup[3].seconds = dup[1].seconds;
  try {
    checkBracket(dup);
    FAIL();
  } catch (const HdrError& e) {
    EXPECT_NE(std::string(e.what()).find("duplicate exposure time"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(dup[3].name), std::string::npos);
  }
  auto sizes = bracket;
  sizes[2].image.width = 16;
  sizes[2].image.pixels.resize(16 * 24 * 3);
  EXPECT_THROW(checkBracket(sizes), HdrError);
  auto zero = bracket;
  zero[0].seconds = 0;
  EXPECT_THROW(checkBracket(zero), HdrError);
  auto nan = bracket;
  nan[0].seconds = std::nan("");
  EXPECT_THROW(checkBracket(nan), HdrError);
  // Every pixel clipped in every exposure: nothing to learn from.
  auto clipped = bracket;
  for (Exposure& e : clipped) std::fill(e.image.pixels.begin(), e.image.pixels.end(), uint8_t{255});
  EXPECT_THROW(recoverResponse(clipped), HdrError);
}

}  // namespace
}  // namespace penumbra::lighting
