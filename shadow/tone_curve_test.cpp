#include "shadow/tone_curve.h"

#include <gtest/gtest.h>

#include <array>
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

// operator() (bucket table + scan) against the definition (binary search) on the inputs
// where a bucketing mistake would show: every threshold and its double and float
// neighbours, a sweep over many octaves in floats and in doubles between floats, signed
// zeros, denormals, values beyond the largest float, infinities and NaN; and curves whose
// thresholds are -inf (every radiance reaches the code) or +inf (never reached).
TEST(ToneCurve, TheBucketTableEqualsTheBinarySearch) {
  const double inf = std::numeric_limits<double>::infinity();
  std::array<double, 255> steps{};
  for (int k = 0; k < 255; ++k) steps[size_t(k)] = k < 3 ? -inf : k > 250 ? inf : 1e-3 * k * k;
  const std::array<ToneCurve::Sample, 2> linear = {{{0.0, 0.0}, {255.0, 255.0}}};
  for (const ToneCurve& curve :
       {ToneCurve::gamma(1.2, 2.2), ToneCurve::gamma(40.0, 1.0), ToneCurve::gamma(1e-40, 3.0),
        ToneCurve::fromThresholds(steps), ToneCurve::fromSamples(linear)}) {
    auto same = [&](double x) { ASSERT_EQ(curve(x), curve.bySearch(x)) << x; };
    for (int k = 1; k <= 255; ++k) {
      const double t = curve.threshold(k);
      const float tf = static_cast<float>(t);
      for (double x : {t, std::nextafter(t, -inf), std::nextafter(t, inf), double(tf),
                       double(std::nextafter(tf, 0.0f)), double(std::nextafter(tf, 1e30f))}) {
        same(x);
      }
    }
    for (float x = 1e-9f; x < 1e6f; x *= 1.0007f) {
      same(double(x));
      same(std::nextafter(double(x), inf));  // doubles between two floats
      same(std::nextafter(double(x), 0.0));
    }
    // The ends of the range operator() reads straight from a double's bits, [2^-126, 2^128),
    // and random doubles of every exponent.
    for (double x : {std::ldexp(1.0, -126), std::nextafter(std::ldexp(1.0, -126), 0.0),
                     std::ldexp(1.0, 128), std::nextafter(std::ldexp(1.0, 128), 0.0)}) {
      same(x);
    }
    uint64_t state = 12345;
    for (int i = 0; i < 200000; ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      const double x =
          std::ldexp(1.0 + double(state >> 12) * 0x1p-52, int(state >> 56) % 300 - 150);
      same(x);
    }
    for (double x : {0.0, -0.0, 1e-320, 1e-45, double(std::numeric_limits<float>::max()),
                     std::nextafter(double(std::numeric_limits<float>::max()), inf), 1e300, inf,
                     -1.0, -1e-300, -inf, std::numeric_limits<double>::quiet_NaN()}) {
      same(x);
    }
  }
  EXPECT_EQ(ToneCurve::gamma(1.2, 2.2)(std::numeric_limits<double>::quiet_NaN()), 0);
  // A default-constructed curve (all thresholds 0) shares a saturated table.
  EXPECT_EQ(ToneCurve()(1.0), 255);
  EXPECT_EQ(ToneCurve()(-1.0), 0);
}

TEST(ToneInverse, CodesRoundTripThroughT) {
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  const ToneInverse inverse(tone);
  EXPECT_EQ(inverse(0), 0.0f);
  for (int c = 1; c < 256; ++c) EXPECT_EQ(tone(double(inverse(uint8_t(c)))), c) << c;
}

// levels(): the continuous T behind the codes. Non-decreasing, within half a level of the
// code (so rounding it gives the code, ties aside), through k - 0.5 at each threshold,
// continuous inside a code's interval, and flat where the curve never steps.
TEST(ToneCurveLevels, ContinuousMonotoneAndWithinHalfALevelOfTheCode) {
  for (const ToneCurve& tone : {ToneCurve::gamma(1.2, 2.2), ToneCurve::gamma(3.0, 1.0)}) {
    double last = 0;
    for (int i = 0; i <= 200000; ++i) {
      const double radiance = 1.2 * i / 200000.0;
      const double value = tone.levels(radiance);
      ASSERT_GE(value, last - 1e-9) << radiance;
      ASSERT_LE(std::abs(value - tone(radiance)), 0.5 + 1e-9) << radiance;
      last = value;
    }
    for (int k = 1; k < 255; ++k) {
      ASSERT_NEAR(tone.levels(tone.threshold(k)), k - 0.5, 1e-9) << k;
    }
    EXPECT_EQ(tone.levels(0.0), 0.0);
    EXPECT_EQ(tone.levels(-1.0), 0.0);
    EXPECT_EQ(tone.levels(std::numeric_limits<double>::quiet_NaN()), 0.0);
    EXPECT_EQ(tone.levels(1e9), 255.0);
  }
  // Linear samples: levels() is the line itself, not the staircase of the codes.
  const std::vector<ToneCurve::Sample> line{{0.0, 0.0}, {1.0, 255.0}};
  const ToneCurve linear = ToneCurve::fromSamples(line);
  for (double radiance : {0.1, 0.25, 0.3337, 0.5, 0.9}) {
    EXPECT_NEAR(linear.levels(radiance), 255.0 * radiance, 1e-9) << radiance;
  }
  // A curve that never leaves code 0 above its samples' top, and one that starts at 200.
  const std::vector<ToneCurve::Sample> dim{{0.0, 0.0}, {1.0, 100.0}};
  EXPECT_EQ(ToneCurve::fromSamples(dim).levels(5.0), 100.0);
  const std::vector<ToneCurve::Sample> bright{{1.0, 200.0}, {2.0, 255.0}};
  EXPECT_EQ(ToneCurve::fromSamples(bright).levels(0.5), 200.0);
}

}  // namespace
}  // namespace penumbra::shadow
