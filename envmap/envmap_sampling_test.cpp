#include "envmap/envmap_sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/colour.h"
#include "envmap/envmap_test_util.h"

namespace penumbra::envmap {
namespace {

using testutil::angleDegrees;

void expectPowerSumsTo(const LightSet& lights, const glm::dvec3& total) {
  const glm::dvec3 sum = totalPower(lights);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], total[c], 1e-12 * total[c]) << "channel " << c;
}

// A uniform environment: the warp is the identity, every light has the same RGB power, and
// the lights spread evenly: each of 4 equal-solid-angle z bands × 8 azimuth sectors holds
// 256/32 = 8 ± 3 lights, and no two lights are closer than 43% of the mean spacing
// √(2π/256) ≈ 9.0° (measured: 4.13°; the unrelaxed Halton points' closest pair is 3.39°, so
// this checks the Lloyd step's work).
TEST(EnvmapSampling, UniformEnvironmentGivesEvenlySpreadEqualPowerLights) {
  const HemisphereMap map = testutil::uniformMap({1.0f, 0.5f, 0.25f});
  const EnvmapDistribution distribution(map);
  const SamplePattern pattern(256);
  const LightSet lights = distribution.sample(pattern, 256);
  ASSERT_EQ(lights.size(), 256u);
  const glm::dvec3 total = distribution.totalPower();
  EXPECT_NEAR(total.r, 2 * 3.14159265358979323846, 1e-9);
  std::array<int, 32> cells{};
  for (const DirectionalLight& light : lights) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(light.power[c], total[c] / 256, 1e-12 * total[c]);
    const glm::dvec2& s = pattern.point(light.id);
    const glm::dvec3 unwarped = diskToHemisphere(concentricSquareToDisk(s.x, s.y));
    EXPECT_LT(angleDegrees(light.direction, unwarped), 1e-6) << "light " << light.id;
    const double azimuth =
        std::atan2(light.direction.y, light.direction.x) + 3.14159265358979323846;
    const int sector = std::min(7, int(azimuth / (2 * 3.14159265358979323846) * 8));
    ++cells[std::min(3, int(light.direction.z * 4)) * 8 + sector];
  }
  for (int k = 0; k < 32; ++k) EXPECT_NEAR(cells[k], 8, 3) << "cell " << k;
  double closest = 180;
  for (size_t i = 0; i < lights.size(); ++i)
    for (size_t j = i + 1; j < lights.size(); ++j)
      closest = std::min(closest, angleDegrees(lights[i].direction, lights[j].direction));
  const double spacing = std::sqrt(2 * 3.14159265358979323846 / 256) * 180 / 3.14159265358979323846;
  EXPECT_GT(closest, 0.43 * spacing)
      << "closest pair " << closest << "°, spacing " << spacing << "°";
}

// Energy: the lights' RGB powers add up to the map's, whatever the count.
TEST(EnvmapSampling, LightPowersSumToTheMapsPower) {
  const HemisphereMap map = testutil::windowMap();
  const EnvmapDistribution distribution(map);
  const SamplePattern pattern(300);
  for (uint32_t count : {1u, 7u, 72u, 300u})
    expectPowerSumsTo(distribution.sample(pattern, count), distribution.totalPower());
  // The window is ≈ 40× the sky over ≈ 2% of the solid angle: most lights go there.
  const LightSet lights = distribution.sample(pattern, 300);
  const auto inWindow = std::count_if(lights.begin(), lights.end(), [](const DirectionalLight& l) {
    return l.power.b < 0.8 * l.power.r;  // the window's warm colour
  });
  EXPECT_GT(inWindow, 150);
}

// Havran 2005 §3.2: the first k of n lights are the k-light set: the same ids and directions
// (bit for bit); only the common power share changes with the count.
TEST(EnvmapSampling, FirstKOfNLightsAreTheKLightSet) {
  const EnvmapDistribution distribution(testutil::windowMap());
  const SamplePattern pattern(300);
  const LightSet all = distribution.sample(pattern, 300);
  for (uint32_t k : {1u, 50u, 299u}) {
    const LightSet prefix = distribution.sample(pattern, k);
    ASSERT_EQ(prefix.size(), k);
    for (uint32_t i = 0; i < k; ++i) {
      EXPECT_EQ(prefix[i].id, all[i].id);
      EXPECT_EQ(prefix[i].direction, all[i].direction) << "light " << i << " of " << k;
    }
    expectPowerSumsTo(prefix, distribution.totalPower());
  }
  // And a larger pattern gives the same first lights only if it is the same pattern: the
  // relaxation is of the whole pattern (so the set is fixed once, for the largest count).
  const SamplePattern unrelaxed(300, false);
  EXPECT_NE(distribution.sample(unrelaxed, 10)[5].direction, all[5].direction);
}

// Continuity in the map (Havran 2005 §3.1): brightening a 10 × 5 patch of the window moves
// the lights in proportion to the change, without jumps: 0.1% moves none by more than 0.5°,
// and 1% moves them about 10× as far (measured: 0.36° and 3.7°, the largest motions being
// lights beside the window's sharp edge, where the interpolated CDF is steep). A jump (a light
// changing row without interpolation, a Halton index changing hands) would not scale.
TEST(EnvmapSampling, SmallChangeInTheMapMovesLightsALittle) {
  const SamplePattern pattern(300);
  const HemisphereMap base = testutil::windowMap();
  auto maxMotion = [&](float factor) {
    HemisphereMap changed = base;
    for (uint32_t y = 45; y < 50; ++y)
      for (uint32_t x = 80; x < 90; ++x)
        for (int c = 0; c < 3; ++c) changed.radiance.pixel(x, y)[c] *= factor;
    const LightSet a = EnvmapDistribution(base).sample(pattern, 300);
    const LightSet b = EnvmapDistribution(changed).sample(pattern, 300);
    double worst = 0;
    for (size_t i = 0; i < a.size(); ++i)
      worst = std::max(worst, angleDegrees(a[i].direction, b[i].direction));
    return worst;
  };
  const double tiny = maxMotion(1.0001f), small = maxMotion(1.001f), larger = maxMotion(1.01f);
  EXPECT_LT(small, 0.5) << "max light motion for a 0.1% change";
  EXPECT_GT(small, 0.0);
  EXPECT_NEAR(larger / small, 10.0, 3.0) << "motion " << small << "° and " << larger << "°";
  EXPECT_NEAR(small / tiny, 10.0, 3.0) << "motion " << tiny << "° and " << small << "°";
}

// Continuity of the warp between rows: rows alternate between energy in the left and the
// right half of the azimuths. Without interpolating neighbouring conditional CDFs the azimuth
// would jump by about half a turn at each row boundary; with it, a sweep of u in 20,000 steps
// of 2.5e-6 across several rows never moves the direction by more than 0.2°.
TEST(EnvmapSampling, WarpIsContinuousAcrossRowBoundaries) {
  HemisphereMap map = testutil::uniformMap({0.1f, 0.1f, 0.1f});
  for (uint32_t y = 0; y < kEnvmapRows; ++y)
    for (uint32_t x = 0; x < kEnvmapCols; ++x)
      if ((x < kEnvmapCols / 2) == (y % 2 == 0))
        for (int c = 0; c < 3; ++c) map.radiance.pixel(x, y)[c] = 5.0f;
  const EnvmapDistribution distribution(map);
  double worst = 0;
  glm::dvec3 previous = diskToHemisphere(distribution.warp({0.40, 0.3}));
  for (int step = 1; step <= 20000; ++step) {
    const glm::dvec3 d = diskToHemisphere(distribution.warp({0.40 + 0.05 * step / 20000, 0.3}));
    worst = std::max(worst, angleDegrees(previous, d));
    previous = d;
  }
  EXPECT_LT(worst, 0.2);
}

TEST(EnvmapSampling, BadMapsAreRefusedWithTheirNameAndPixel) {
  HemisphereMap map = testutil::uniformMap({1, 1, 1}, 8, 4);
  map.radiance.pixel(3, 2)[1] = -0.5f;
  try {
    EnvmapDistribution bad(map, "probe.exr");
    FAIL() << "negative radiance accepted";
  } catch (const EnvmapError& e) {
    EXPECT_NE(std::string(e.what()).find("probe.exr: pixel (3, 2)"), std::string::npos) << e.what();
  }
  // Every kind of bad sample, in the first, a middle and the last row and column (the rows are
  // checked as a whole, then searched for the sample to name).
  for (const float bad : {-0.5f, -1e-30f, std::nanf(""), -std::nanf(""), HUGE_VALF, -HUGE_VALF})
    for (const auto& [col, row, c] :
         std::array<std::array<uint32_t, 3>, 3>{{{0, 0, 0}, {3, 2, 1}, {7, 3, 2}}}) {
      HemisphereMap one = testutil::uniformMap({1, 1, 1}, 8, 4);
      one.radiance.pixel(col, row)[c] = bad;
      const std::string where =
          "probe.exr: pixel (" + std::to_string(col) + ", " + std::to_string(row) + ")";
      try {
        EnvmapDistribution refused(one, "probe.exr");
        FAIL() << "radiance " << bad << " accepted at " << where;
      } catch (const EnvmapError& e) {
        EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
      }
    }
  HemisphereMap negativeZero = testutil::uniformMap({1, 1, 1}, 8, 4);
  negativeZero.radiance.pixel(5, 1)[0] = -0.0f;
  EXPECT_NO_THROW(EnvmapDistribution(negativeZero, "probe.exr"));
  map.radiance.pixel(3, 2)[1] = std::nanf("");
  EXPECT_THROW(EnvmapDistribution(map, "probe.exr"), EnvmapError);
  map.radiance.pixels.pop_back();
  EXPECT_THROW(EnvmapDistribution(map, "probe.exr"), EnvmapError);
  EXPECT_THROW(EnvmapDistribution(HemisphereMap{}, "empty"), EnvmapError);
  EnvmapDistribution ok(testutil::uniformMap({1, 1, 1}, 8, 4));
  EXPECT_THROW(ok.sample(SamplePattern(4), 5), EnvmapError);
  EXPECT_THROW(ok.update(map, "probe.exr"), EnvmapError);
  EXPECT_THROW(ok.sample(SamplePattern(4), 4), EnvmapError);  // left empty, not half-built
}

// The CDFs as they were built before the build was fused into one pass per row (the division
// of a row done while the next row is summed; the checks without a branch per sample): one
// row at a time, checked sample by sample, normalised after it. The warp from them, written out
// again here, must give the same bits as EnvmapDistribution's for maps with odd column counts,
// black rows (the uniform CDF) at the top, the middle and the bottom, and −0 samples.
struct ReferenceCdfs {
  std::vector<double> marginal, conditional;
  uint32_t rows = 0, cols = 0;

  explicit ReferenceCdfs(const HemisphereMap& map) : rows(map.rows()), cols(map.cols()) {
    const auto normalise = [](double* cdf, size_t bins) {
      const double total = cdf[bins];
      for (size_t k = 1; k < bins; ++k)
        cdf[k] = total > 0 ? cdf[k] / total : double(k) / double(bins);
      cdf[bins] = 1.0;
    };
    marginal.assign(rows + 1, 0.0);
    conditional.assign(size_t(rows) * (cols + 1), 0.0);
    for (uint32_t row = 0; row < rows; ++row) {
      double* cdf = &conditional[size_t(row) * (cols + 1)];
      for (uint32_t col = 0; col < cols; ++col) {
        const float* p = map.radiance.pixel(col, row);
        cdf[col + 1] = cdf[col] + core::luminance(glm::dvec3(p[0], p[1], p[2]));
      }
      marginal[row + 1] = marginal[row] + cdf[cols];
      normalise(cdf, cols);
    }
    normalise(marginal.data(), rows);
  }

  double at(uint32_t row0, uint32_t row1, double t, uint32_t j) const {
    return (1.0 - t) * conditional[size_t(row0) * (cols + 1) + j] +
           t * conditional[size_t(row1) * (cols + 1) + j];
  }

  static double position(double x, double lo, double hi) {
    return hi > lo ? std::clamp((x - lo) / (hi - lo), 0.0, 1.0) : 0.0;
  }

  DiskPolar warp(const DiskPolar& p) const {
    uint32_t row =
        uint32_t(std::upper_bound(marginal.begin(), marginal.end(), p.u) - marginal.begin());
    row = std::clamp<uint32_t>(row, 1, rows) - 1;
    while (row > 0 && !(marginal[row + 1] > marginal[row])) --row;
    const double u = (row + position(p.u, marginal[row], marginal[row + 1])) / double(rows);
    const double x = u * rows - 0.5;
    uint32_t row0 = 0, row1 = 0;
    double t = 0;
    if (x >= double(rows - 1)) {
      row0 = row1 = rows - 1;
    } else if (x > 0.0) {
      row0 = uint32_t(x);
      row1 = row0 + 1;
      t = x - row0;
    }
    uint32_t lo = 0, hi = cols;
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      (at(row0, row1, t, mid) <= p.turns ? lo : hi) = mid;
    }
    const double turns =
        (lo + position(p.turns, at(row0, row1, t, lo), at(row0, row1, t, lo + 1))) / double(cols);
    return {u, turns < 1.0 ? turns : 0.0};
  }
};

TEST(EnvmapSampling, CdfsAreThoseOfTheRowByRowBuild) {
  for (const auto& [cols, rows] :
       std::array<std::pair<uint32_t, uint32_t>, 5>{{{360, 90}, {7, 5}, {1, 3}, {2, 1}, {13, 1}}}) {
    HemisphereMap map{core::ImageF(cols, rows)};
    for (uint32_t row = 0; row < rows; ++row)
      for (uint32_t col = 0; col < cols; ++col) {
        // Black rows at the top, in the middle and at the bottom (when there are 3 or more);
        // elsewhere a hash of the position, with some −0 and 0 samples.
        const bool black = rows >= 3 && (row == 0 || row == rows / 2 || row == rows - 1);
        for (int c = 0; c < 3; ++c) {
          const uint32_t h = (col * 2654435761u) ^ (row * 40503u) ^ (uint32_t(c) * 977u);
          float v = black ? 0.0f : float(h % 1000) * 0.37f + float(h % 7) * 1e-3f;
          if (h % 11 == 0) v = -0.0f;
          map.radiance.pixel(col, row)[c] = v;
        }
      }
    const EnvmapDistribution distribution(map);
    EnvmapDistribution reused(testutil::uniformMap({1, 2, 3}, cols, rows));
    reused.update(map);
    const ReferenceCdfs reference(map);
    for (int i = 0; i <= 64; ++i)
      for (int j = 0; j <= 64; ++j) {
        const DiskPolar p{i / 64.0, j / 64.5};
        const DiskPolar expected = reference.warp(p), got = distribution.warp(p),
                        again = reused.warp(p);
        ASSERT_EQ(got.u, expected.u) << cols << " x " << rows << " at " << i << ", " << j;
        ASSERT_EQ(got.turns, expected.turns) << cols << " x " << rows << " at " << i << ", " << j;
        ASSERT_EQ(again.u, expected.u);
        ASSERT_EQ(again.turns, expected.turns);
      }
  }
}

// A black map: no power, and the lights still have directions (the uniform ones).
TEST(EnvmapSampling, BlackMapGivesZeroPowerLights) {
  const EnvmapDistribution distribution(testutil::uniformMap({0, 0, 0}));
  const LightSet lights = distribution.sample(SamplePattern(16), 16);
  for (const DirectionalLight& light : lights) {
    EXPECT_EQ(light.power, glm::dvec3(0.0));
    EXPECT_NEAR(glm::length(light.direction), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace penumbra::envmap
