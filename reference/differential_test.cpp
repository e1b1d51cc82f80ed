#include "reference/differential.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra::reference {
namespace {

// Every code T can output comes back from T(T^-1(code)), so differential rendering with
// no shadow returns the photograph byte for byte.
TEST(InverseTone, RoundTripsEveryCodeOfTheDisplayCurve) {
  for (const shadow::ToneCurve& tone :
       {shadow::ToneCurve::gamma(1.2, 2.2), shadow::ToneCurve::gamma(0.05, 1.0),
        shadow::ToneCurve::gamma(7.0, 2.6)}) {
    for (int k = 0; k < 256; ++k) {
      const double l = inverseTone(tone, static_cast<uint8_t>(k));
      EXPECT_EQ(tone(l), k) << k;
      if (k > 0 && k < 255) {
        // The midpoint of the code's radiance interval.
        EXPECT_DOUBLE_EQ(l, 0.5 * (tone.threshold(k) + tone.threshold(k + 1))) << k;
      }
    }
    EXPECT_DOUBLE_EQ(inverseTone(tone, 0), 0.5 * tone.threshold(1));
    EXPECT_EQ(inverseTone(tone, 255), tone.threshold(255));
  }
}

TEST(InverseTone, CodesTheCurveNeverOutputsFallToTheNearestLowerOne) {
  // Codes 11..20 share one threshold (T jumps from 10 to 20); codes above 200 are never
  // reached.
  std::array<double, 255> t{};
  for (int k = 1; k <= 255; ++k) {
    double v = k <= 10 ? k : (k <= 20 ? 20.0 : double(k));
    if (k > 200) v = INFINITY;
    t[size_t(k - 1)] = v;
  }
  const shadow::ToneCurve tone = shadow::ToneCurve::fromThresholds(t);
  EXPECT_EQ(tone(inverseTone(tone, 10)), 10);
  EXPECT_DOUBLE_EQ(inverseTone(tone, 10), 15.0);  // [10, 20)
  for (int k = 11; k < 20; ++k) {
    EXPECT_EQ(inverseTone(tone, static_cast<uint8_t>(k)), inverseTone(tone, 10)) << k;
  }
  EXPECT_EQ(tone(inverseTone(tone, 20)), 20);
  EXPECT_EQ(tone(inverseTone(tone, 200)), 200);
  EXPECT_EQ(inverseTone(tone, 230), inverseTone(tone, 200));
  EXPECT_TRUE(std::isfinite(inverseTone(tone, 255)));
}

TEST(ComposeDifferential, SubtractsTheBlockedLightAndMixesTheProductByCoverage) {
  ReferenceImage image;
  image.width = 3;
  image.height = 1;
  image.noObject.assign(3, glm::vec3(0));
  image.withObject.assign(3, glm::vec3(0));
  image.roomDelta = {glm::vec3(0), glm::vec3(0.1f, 0.2f, 0.3f), glm::vec3(0)};
  image.objectRadiance = {glm::vec3(0), glm::vec3(0), glm::vec3(0.5f)};
  image.objectCoverage = {0.0f, 0.0f, 1.0f};
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(1.0, 1.0);  // code ~ 255 L
  const std::vector<uint8_t> background = {100, 100, 100, 255, 200, 200, 200, 255, 50, 50, 50, 255};
  const DifferentialFrame f = composeDifferential(image, background, tone);
  const double lb = inverseTone(tone, 200);
  EXPECT_EQ(f.rgba[0], 100);
  EXPECT_EQ(f.rgba[4], tone(lb - double(0.1f)));
  EXPECT_EQ(f.rgba[5], tone(lb - double(0.2f)));
  EXPECT_EQ(f.rgba[6], tone(lb - double(0.3f)));
  EXPECT_EQ(f.rgba[8], tone(0.5));
  EXPECT_EQ(f.shadowMask, (std::vector<uint8_t>{0, 255, 0}));
  EXPECT_EQ(f.shadowPixels, 1u);
  EXPECT_EQ(f.objectPixels, 1u);
}

TEST(ComposeDifferential, ChangedPixelsNoiseAndMaskImage) {
  DifferentialFrame a;
  a.width = 3;
  a.height = 1;
  a.rgba = {10, 10, 10, 255, 20, 20, 20, 255, 30, 30, 30, 255};
  a.shadowMask = {0, 255, 0};
  const std::vector<uint8_t> background = {10, 10, 10, 255, 90, 20, 20, 255, 30, 30, 31, 7};
  EXPECT_EQ(changedPixels(a, background), 2u) << "alpha is not compared";

  DifferentialFrame b = a;
  b.rgba[4] = 24;  // +4 in one channel of the shared shadow pixel
  b.shadowMask = {0, 255, 255};
  b.rgba[8] = 27;  // -3 in the pixel only b's mask holds
  size_t samples = 0;
  // Two shadow pixels x 3 channels; squared differences 16 + 9 over 6 samples, halved.
  EXPECT_DOUBLE_EQ(shadowNoiseRms(a, b, &samples), std::sqrt(25.0 / 6.0 / 2.0));
  EXPECT_EQ(samples, 6u);
  b.rgba[0] = 0;  // outside both masks: not counted
  EXPECT_DOUBLE_EQ(shadowNoiseRms(a, b), std::sqrt(25.0 / 6.0 / 2.0));
  a.shadowMask = b.shadowMask = {0, 0, 0};
  EXPECT_EQ(shadowNoiseRms(a, b, &samples), 0.0);
  EXPECT_EQ(samples, 0u);

  b.shadowMask = {0, 255, 0};
  EXPECT_EQ(shadowMaskRgba(b),
            (std::vector<uint8_t>{0, 0, 0, 255, 255, 255, 255, 255, 0, 0, 0, 255}));
}

// Each code's interval holds exactly the radiances T maps to it: its ends map to the code,
// and one step past either end does not.
TEST(ToneInterval, HoldsExactlyTheRadiancesOfItsCode) {
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(1.2, 2.2);
  for (int k = 0; k < 256; ++k) {
    const ToneInterval r = toneInterval(tone, static_cast<uint8_t>(k));
    EXPECT_EQ(tone(r.lo), k) << k;
    EXPECT_EQ(tone(r.hi), k) << k;
    EXPECT_LE(r.lo, inverseTone(tone, static_cast<uint8_t>(k)));
    EXPECT_GE(r.hi, inverseTone(tone, static_cast<uint8_t>(k)));
    if (k > 0) {
      EXPECT_EQ(tone(std::nextafter(r.lo, -INFINITY)), k - 1) << k;
    }
    if (k < 255) {
      EXPECT_EQ(tone(std::nextafter(r.hi, INFINITY)), k + 1) << k;
    }
  }
  EXPECT_EQ(toneInterval(tone, 0).lo, 0.0);
}

// The bounds hold the frame in every sample; with nothing taken away they are the
// photograph's own byte; where a shadow takes nearly all the light of a floor photographed
// at code 103 (gamma 2.2), the photograph's half-code uncertainty spans many levels.
TEST(ComposeDifferential, BoundsHoldTheFrameAndWidenNearBlack) {
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(1.2, 2.2);
  const double lb = inverseTone(tone, 103);
  ReferenceImage image;
  image.width = 4;
  image.height = 1;
  image.noObject.assign(4, glm::vec3(0));
  image.withObject.assign(4, glm::vec3(0));
  image.roomDelta = {glm::vec3(0), glm::vec3(float(0.5 * lb)), glm::vec3(float(0.995 * lb)),
                     glm::vec3(0)};
  image.objectRadiance = {glm::vec3(0), glm::vec3(0), glm::vec3(0), glm::vec3(0.05f)};
  image.objectCoverage = {0.0f, 0.0f, 0.0f, 1.0f};
  const std::vector<uint8_t> background(16, 103);
  const DifferentialFrame f = composeDifferential(image, background, tone);
  for (size_t i = 0; i < 16; ++i) {
    if (i % 4 == 3) continue;
    EXPECT_LE(f.lower[i], f.rgba[i]) << i;
    EXPECT_LE(f.rgba[i], f.upper[i]) << i;
  }
  EXPECT_EQ(f.lower[0], 103);
  EXPECT_EQ(f.upper[0], 103);
  EXPECT_LE(f.upper[4] - f.lower[4], 2) << "half the light taken: about a code either way";
  EXPECT_EQ(f.lower[8], 0) << "the photograph's low end leaves nothing";
  EXPECT_EQ(f.upper[8], 16) << "its high end leaves 1.6 % of the floor's radiance";
  EXPECT_EQ(f.rgba[8], 9);
  // The product's own pixel does not depend on the photograph at all.
  EXPECT_EQ(f.lower[12], f.rgba[12]);
  EXPECT_EQ(f.upper[12], f.rgba[12]);
}

}  // namespace
}  // namespace penumbra::reference
