#include "envmap/light_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "core/random.h"
#include "envmap/envmap_sampling.h"
#include "envmap/envmap_test_util.h"

namespace penumbra::envmap {
namespace {

using testutil::angleDegrees;
constexpr double kPi = 3.14159265358979323846;

// |H(f)| of the FIR at frequency f for sampling rate fs.
double gain(const FirTaps& taps, double f, double fs) {
  std::complex<double> h = 0;
  for (size_t k = 0; k < kFirTaps; ++k)
    h += taps[k] * std::polar(1.0, -2 * kPi * f / fs * double(k));
  return std::abs(h);
}

// Havran 2005 §3.3: the printed taps sum to 1.09245 (a DC gain of +0.77 dB, energy not
// preserved); normalised, the DC gain is 1, the response stays symmetric (linear phase, delay
// 4 frames), and the stop band (9–10.5 Hz at 21 Hz sampling) is at least 21 dB down.
TEST(LightFilter, NormalisedTapsPreserveEnergyAndCutHighFrequencies) {
  double printed = 0;
  for (double w : kHavranFirPrinted) printed += w;
  EXPECT_NEAR(printed, 1.09245, 1e-12);
  const FirTaps taps = normalisedHavranFir();
  double sum = 0;
  for (size_t k = 0; k < kFirTaps; ++k) {
    sum += taps[k];
    EXPECT_EQ(taps[k], taps[kFirTaps - 1 - k]);
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_NEAR(gain(taps, 0, 21), 1.0, 1e-15);
  EXPECT_GT(gain(taps, 2, 21), 0.84);
  for (double f : {9.0, 10.0, 10.5}) EXPECT_LT(gain(taps, f, 21), 0.09) << f << " Hz";
}

LightSet lightsAt(const glm::dvec3& power, double tilt, uint32_t count) {
  LightSet lights;
  for (uint32_t i = 1; i <= count; ++i)
    lights.push_back({i, glm::normalize(glm::dvec3(std::sin(tilt + 0.1 * i), 0.2, 1.0)), power});
  return lights;
}

TEST(LightFilter, ConstantInputPassesUnchanged) {
  TemporalLightFilter filter;
  const LightSet lights = lightsAt({1.0, 2.0, 3.0}, 0.3, 12);
  for (int frame = 0; frame < 20; ++frame) {
    const LightSet out = filter.push(lights);
    ASSERT_EQ(out.size(), lights.size());
    for (size_t i = 0; i < out.size(); ++i) {
      EXPECT_EQ(out[i].id, lights[i].id);
      EXPECT_LT(angleDegrees(out[i].direction, lights[i].direction), 1e-9);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[i].power[c], lights[i].power[c], 1e-14);
    }
  }
}

// Energy through the filter: every frame the lights add up to the filtered total, and over a
// sequence that is constant at both ends (a lamp switched off at frame 10) the filtered total
// adds up to the input's plus the 4-frame delay's share: Σy = Σx + (first − last) Σ k w_k, with
// Σ k w_k = 4 for the symmetric taps. The printed taps would miss by 9%.
TEST(LightFilter, EnergyIsConservedThroughTheFilter) {
  TemporalLightFilter filter;
  const double first = 10.0, last = 3.0;
  double inputSum = 0, outputSum = 0;
  for (int frame = 0; frame < 40; ++frame) {
    const double total = frame < 10 ? first : last;
    inputSum += total;
    const LightSet out = filter.push(lightsAt(glm::dvec3(total / 8), 0.01 * frame, 8));
    const glm::dvec3 sum = totalPower(out);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], filter.filteredTotalPower()[c], 1e-12);
    outputSum += filter.filteredTotalPower().r;
  }
  EXPECT_NEAR(outputSum, inputSum + 4 * (first - last), 1e-9);
}

// Lights are tracked by id: a light that appears later starts from its own direction, and
// one that skipped a frame is not pulled towards where it was before.
TEST(LightFilter, LightsAreTrackedByTheirIds) {
  TemporalLightFilter filter;
  for (int frame = 0; frame < 5; ++frame) filter.push(lightsAt({1, 1, 1}, 0.0, 10));
  const LightSet more = lightsAt({1, 1, 1}, 1.0, 20);
  const LightSet out = filter.push(more);
  EXPECT_LT(angleDegrees(out[14].direction, more[14].direction), 1e-9);  // id 15: new
  EXPECT_GT(angleDegrees(out[3].direction, more[3].direction), 1.0);     // id 4: filtered
  LightSet bad = more;
  bad[2].id = 0;
  EXPECT_THROW(filter.push(bad), std::invalid_argument);
}

// A noisy environment (5% per-pixel sensor noise and 3% frame gain noise, a window):
// mean frame-to-frame motion of the lights and change of total power, unfiltered against
// filtered. White noise through these taps keeps √(Σ(w_k − w_{k−1})² / 2) ≈ 0.54 of its
// frame-to-frame change; the test asks for less than 0.7.
TEST(LightFilter, FlickerIsReducedAgainstUnfiltered) {
  const HemisphereMap base = testutil::windowMap();
  const SamplePattern pattern(100);
  TemporalLightFilter filter;
  LightSet previousRaw, previousFiltered;
  double rawMotion = 0, filteredMotion = 0, rawPower = 0, filteredPower = 0;
  int measured = 0;
  for (uint64_t frame = 0; frame < 60; ++frame) {
    HemisphereMap map = base;
    const double frameGain = 1.0 + 0.03 * (2 * core::unitSample(7, frame) - 1);
    for (size_t i = 0; i < map.radiance.pixels.size(); ++i)
      map.radiance.pixels[i] *=
          float(frameGain * (1.0 + 0.05 * (2 * core::unitSample(frame, i) - 1)));
    const LightSet raw = EnvmapDistribution(map).sample(pattern, 100);
    const LightSet filtered = filter.push(raw);
    if (frame >= kFirTaps) {  // the filter's history holds real frames only
      for (size_t i = 0; i < raw.size(); ++i) {
        rawMotion += angleDegrees(raw[i].direction, previousRaw[i].direction);
        filteredMotion += angleDegrees(filtered[i].direction, previousFiltered[i].direction);
      }
      rawPower += std::fabs(totalPower(raw).g - totalPower(previousRaw).g);
      filteredPower += std::fabs(totalPower(filtered).g - totalPower(previousFiltered).g);
      ++measured;
    }
    previousRaw = raw;
    previousFiltered = filtered;
  }
  rawMotion /= measured * 100.0;
  filteredMotion /= measured * 100.0;
  std::printf(
      "flicker: mean light motion per frame %.4f° unfiltered, %.4f° filtered (%.2f); "
      "mean |Δ total power| %.4f unfiltered, %.4f filtered (%.2f)\n",
      rawMotion, filteredMotion, filteredMotion / rawMotion, rawPower / measured,
      filteredPower / measured, filteredPower / rawPower);
  RecordProperty("motion_ratio", std::to_string(filteredMotion / rawMotion));
  EXPECT_GT(rawMotion, 0.01);  // the noise does move the lights
  EXPECT_LT(filteredMotion, 0.7 * rawMotion);
  EXPECT_LT(filteredPower, 0.7 * rawPower);
}

}  // namespace
}  // namespace penumbra::envmap
