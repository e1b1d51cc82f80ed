#include "shadow/intensity_transfer.h"
#include "core/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace penumbra::shadow {
namespace {

using glm::dvec3;

TEST(SourceSet, DeterministicAndBalanced) {
  int ones = 0;
  for (uint64_t id = 0; id < 10000; ++id) {
    const int s = sourceSet(42, id);
    ASSERT_TRUE(s == 1 || s == 2);
    EXPECT_EQ(s, sourceSet(42, id));
    ones += s == 1;
  }
  EXPECT_NEAR(ones, 5000, 300);
  // Known values pin the hash: a change would silently re-shade every trace.
  EXPECT_EQ(core::splitmix64(0), 0xE220A8397B1DCDAFull);
  int differ = 0;
  for (uint64_t id = 0; id < 64; ++id) differ += sourceSet(1, id) != sourceSet(2, id);
  EXPECT_GT(differ, 10);
}

TEST(IntensityTransfer, TelescopesWithinEachSet) {
  const ToneCurve tone = ToneCurve::gamma(3.0);
  uint64_t state = 7;
  for (int trial = 0; trial < 200; ++trial) {
    const size_t n = 1 + core::splitmix64(state++) % 50;
    std::vector<dvec3> l(n);
    std::vector<uint8_t> sets(n);
    dvec3 total(0.01 * static_cast<double>(core::splitmix64(state++) % 10));
    for (size_t j = 0; j < n; ++j) {
      for (int c = 0; c < 3; ++c)
        l[j][c] = 0.02 * static_cast<double>(core::splitmix64(state++) % 1000) / 1000;
      total += l[j];
      sets[j] = static_cast<uint8_t>(sourceSet(99, j));
    }
    std::sort(l.begin(), l.end(),
              [](const dvec3& a, const dvec3& b) { return a.x + a.y + a.z > b.x + b.y + b.z; });
    std::vector<core::Rgb8> s(n);
    intensityTransfers(total, l, sets, tone, s);
    for (int set = 1; set <= 2; ++set) {
      dvec3 v = total;  // sequential subtraction, exactly as Fig. 4 accumulates
      std::array<int, 3> sum{};
      for (size_t j = 0; j < n; ++j) {
        if (sets[j] != set) continue;
        v -= l[j];
        sum[0] += s[j].r;
        sum[1] += s[j].g;
        sum[2] += s[j].b;
      }
      const core::Rgb8 t0 = tone.map(total), t1 = tone.map(v);
      EXPECT_EQ(sum[0], t0.r - t1.r);
      EXPECT_EQ(sum[1], t0.g - t1.g);
      EXPECT_EQ(sum[2], t0.b - t1.b);
    }
  }
}

TEST(IntensityTransfer, SingleSetRemovesAllLight) {
  // Every source in one set and L_i = sum L_ij: the transfers add up to T(L_i).
  const ToneCurve tone = ToneCurve::gamma(1.0);
  const std::vector<dvec3> l = {dvec3(0.3, 0.2, 0.1), dvec3(0.2, 0.2, 0.1), dvec3(0.1, 0.05, 0.0)};
  const dvec3 total = l[0] + l[1] + l[2];
  const std::vector<uint8_t> sets(3, 1);
  std::vector<core::Rgb8> s(3);
  intensityTransfers(total, l, sets, tone, s);
  const core::Rgb8 t = tone.map(total);
  EXPECT_EQ(s[0].r + s[1].r + s[2].r, t.r);
  EXPECT_EQ(s[0].g + s[1].g + s[2].g, t.g);
  // The brightest source first takes the smallest step of the concave curve's top.
  EXPECT_GT(s[0].r, 0);
  EXPECT_THROW(intensityTransfers(total, l, std::vector<uint8_t>{1, 3, 1}, tone, s),
               std::invalid_argument);
}

TEST(IntensityTransfersForOcclusion, EndpointsAreExact) {
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  const glm::dvec3 total(0.8, 0.7, 0.6);
  const std::vector<glm::dvec3> l = {
      {0.2, 0.1, 0.05}, {0.1, 0.1, 0.1}, {0.05, 0.2, 0.02}, {0.1, 0.05, 0.1}};
  std::vector<core::Rgb8> s(l.size());
  // q = 1: the drops telescope: all occluded gives exactly T(L - sum).
  intensityTransfersForOcclusion(total, l, 1.0, tone, s);
  glm::dvec3 rest = total;
  int r = tone.map(total).r, g = tone.map(total).g, b = tone.map(total).b;
  for (size_t j = 0; j < l.size(); ++j) {
    rest -= l[j];
    r -= s[j].r;
    g -= s[j].g;
    b -= s[j].b;
  }
  EXPECT_EQ(r, tone.map(rest).r);
  EXPECT_EQ(g, tone.map(rest).g);
  EXPECT_EQ(b, tone.map(rest).b);
  // q = 0: each drop is exact for that source alone.
  intensityTransfersForOcclusion(total, l, 0.0, tone, s);
  for (size_t j = 0; j < l.size(); ++j) {
    EXPECT_EQ(s[j].g, tone.map(total).g - tone.map(total - l[j]).g) << j;
  }
  EXPECT_THROW(intensityTransfersForOcclusion(total, l, 1.5, tone, s), std::invalid_argument);
}

// 8.8 S (core::Rgb16): the drops of ToneCurve::levels() rounded to 1/256 level. They
// telescope like the codes' within 1/512 level per source, agree with the whole-level S
// within a level, and resolve sources far below one level each (100 sources of a panel).
TEST(IntensityTransfersForOcclusion, FineTransfersTelescopeToOne256thOfALevel) {
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  const glm::dvec3 total(0.8, 0.7, 0.6);
  std::vector<glm::dvec3> l(100, glm::dvec3(0.004, 0.0035, 0.003));
  std::vector<core::Rgb16> fine(l.size());
  std::vector<core::Rgb8> whole(l.size());
  intensityTransfersForOcclusion(total, l, 1.0, tone, fine);
  intensityTransfersForOcclusion(total, l, 1.0, tone, whole);
  glm::dvec3 rest = total;
  double sum = 0;
  for (size_t j = 0; j < l.size(); ++j) {
    rest -= l[j];
    sum += fine[j].g / 256.0;
    EXPECT_GT(fine[j].g, 0) << "every faint source keeps its share " << j;
    EXPECT_LE(std::abs(fine[j].g / 256.0 - whole[j].g), 1.0) << j;
  }
  const double exact = tone.levels(total.y) - tone.levels(rest.y);
  EXPECT_NEAR(sum, exact, 100 / 512.0);
  // The whole-level S telescope too, but each is 0 or 1: the drop lands on whichever
  // source crosses a code, so a pixel that some of the sources light sees up to a level per
  // source wrong; the fine ones spread it evenly.
  int wholeSum = 0;
  auto [lo, hi] = std::minmax_element(fine.begin(), fine.end(),
                                      [](const auto& a, const auto& b) { return a.g < b.g; });
  for (const core::Rgb8& c : whole) {
    wholeSum += c.g;
    EXPECT_LE(c.g, 1);
  }
  EXPECT_EQ(wholeSum, tone.map(total).g - tone.map(rest).g);
  EXPECT_NEAR(sum, wholeSum, 1.0);
  EXPECT_LT(hi->g - lo->g, 64) << "fine S of equal sources differ by under a quarter level";
}

// Per-cluster shares: where the pattern of occluded clusters repeats (q_k = 1 for the
// occluded ones, 0 for the others) the occluded clusters' drops telescope to exactly
// T(L) - T(L - their sum), for every pattern; one share for all clusters (the measured
// transfer-weighted share) misses some patterns. A constant q gives the scalar function's S.
TEST(IntensityTransfersForOcclusions, RepeatedPatternsAreExact) {
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  const glm::dvec3 total(0.8, 0.7, 0.6);
  std::vector<glm::dvec3> l;
  for (int j = 0; j < 8; ++j) l.emplace_back(0.09 - 0.01 * j, 0.06 + 0.003 * j, 0.02 + 0.01 * j);
  const size_t n = l.size();
  glm::dvec3 all(0.0);
  for (const glm::dvec3& t : l) all += t;
  std::vector<core::Rgb8> s(n), single(n);
  std::vector<double> q(n);
  int scalarMisses = 0;
  for (uint32_t pattern = 0; pattern < (1u << n); ++pattern) {
    glm::dvec3 rest = total, blocked(0.0);
    for (size_t j = 0; j < n; ++j) {
      q[j] = (pattern >> j) & 1u ? 1.0 : 0.0;
      rest -= q[j] * l[j];
      blocked += q[j] * l[j];
    }
    intensityTransfersForOcclusions(total, l, q, tone, s);
    const double share = (blocked.r + blocked.g + blocked.b) / (all.r + all.g + all.b);
    intensityTransfersForOcclusion(total, l, std::min(share, 1.0), tone, single);
    int exact = tone.map(total).g, scalar = exact;
    for (size_t j = 0; j < n; ++j) {
      if (q[j] == 0.0) continue;
      exact -= s[j].g;
      scalar -= single[j].g;
    }
    ASSERT_EQ(exact, tone.map(rest).g) << "pattern " << pattern;
    scalarMisses += scalar != tone.map(rest).g;
  }
  EXPECT_GT(scalarMisses, 0);
  std::fill(q.begin(), q.end(), 0.4);
  intensityTransfersForOcclusions(total, l, q, tone, s);
  intensityTransfersForOcclusion(total, l, 0.4, tone, single);
  EXPECT_EQ(s, single);
  q[3] = 1.5;
  EXPECT_THROW(intensityTransfersForOcclusions(total, l, q, tone, s), std::invalid_argument);
  q.pop_back();
  EXPECT_THROW(intensityTransfersForOcclusions(total, l, q, tone, s), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
