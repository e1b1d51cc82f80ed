#include "shadow/tone_curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace penumbra::shadow {
namespace {

TEST(ToneCurve, GammaMatchesFormulaAndIsMonotone) {
  const ToneCurve t = ToneCurve::gamma(2.0, 2.2);
  for (int i = 0; i <= 1000; ++i) {
    const double l = 0.6 * i / 1000.0;
    const double ideal = 255.0 * std::pow(std::min(1.0, 2.0 * l), 1 / 2.2);
    EXPECT_NEAR(t(l), ideal, 0.5 + 1e-6) << l;
    if (i > 0) {
      EXPECT_GE(t(l), t(0.6 * (i - 1) / 1000.0));
    }
  }
  EXPECT_EQ(t(0), 0);
  EXPECT_EQ(t(-1), 0);
  EXPECT_EQ(t(std::nan("")), 0);
  EXPECT_EQ(t(1e30), 255);
  EXPECT_EQ(t(std::numeric_limits<double>::infinity()), 255);
}

TEST(ToneCurve, FromSamplesLinear) {
  const std::array<ToneCurve::Sample, 2> s = {{{0.0, 0.0}, {255.0, 255.0}}};
  const ToneCurve t = ToneCurve::fromSamples(s);
  EXPECT_EQ(t(10.49), 10);
  EXPECT_EQ(t(10.5), 11);  // ties round up
  EXPECT_EQ(t(300), 255);
  EXPECT_DOUBLE_EQ(t.threshold(1), 0.5);
  const std::array<ToneCurve::Sample, 2> bad = {{{1.0, 10.0}, {0.5, 20.0}}};
  EXPECT_THROW(ToneCurve::fromSamples(bad), std::invalid_argument);
}

TEST(ToneCurveThresholds, RoundTripAndValidation) {
  const ToneCurve tone = ToneCurve::gamma(1.5, 2.2);
  const ToneCurve back = ToneCurve::fromThresholds(tone.thresholds());
  for (double l = 0.0; l < 1.0; l += 0.0137) EXPECT_EQ(back(l), tone(l)) << l;
  auto bad = tone.thresholds();
  bad[100] = bad[99] - 1.0;
  EXPECT_THROW(ToneCurve::fromThresholds(bad), std::invalid_argument);
}

TEST(ToneLut, SameCodesAsTheToneCurve) {
  for (const ToneCurve& curve : {ToneCurve::gamma(1.2, 2.2), ToneCurve::gamma(40.0, 1.0)}) {
    const ToneLut lut(curve);
    // Every threshold, its float neighbours, and a sweep over many octaves.
    for (int k = 1; k <= 255; ++k) {
      const float t = static_cast<float>(curve.threshold(k));
      for (float x : {t, std::nextafter(t, 0.0f), std::nextafter(t, 1e30f)}) {
        ASSERT_EQ(lut(x), curve(double(x))) << x;
      }
    }
    for (float x = 1e-9f; x < 1e6f; x *= 1.0007f) ASSERT_EQ(lut(x), curve(double(x))) << x;
    EXPECT_EQ(lut(0.0f), curve(0.0));
    EXPECT_EQ(lut(-1.0f), curve(-1.0));
    EXPECT_EQ(lut(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(lut(std::numeric_limits<float>::quiet_NaN()), 0);
  }
}

TEST(ToneInverse, CodesRoundTripThroughT) {
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  const ToneInverse inverse(tone);
  EXPECT_EQ(inverse(0), 0.0f);
  for (int c = 1; c < 256; ++c) EXPECT_EQ(tone(double(inverse(uint8_t(c)))), c) << c;
}

}  // namespace
}  // namespace penumbra::shadow
