#include "shadow/frame_rate_controller.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/clock.h"
#include "shadow/frame_cost_model.h"

namespace penumbra::shadow {
namespace {

using Decision = FrameRateController::Decision;
using Options = FrameRateController::Options;

constexpr int64_t kTarget = 66'666'667;  // 15 fps
constexpr int64_t kFixed = 10'000'000;
constexpr uint64_t kPixelsPerPass = 3'000;

// ~1.08 ms per pass at 256²: 0.6 ms + 65,536 texels × 5 ps + 3,000 pixels × 50 ps.
CostModel::Params kioskCost() {
  return {kFixed, 600'000, 5, 50};
}

Options kioskOptions() {
  Options o;
  o.targetFrameNs = kTarget;
  o.fixedCostNs = kFixed;
  o.minPasses = 4;
  o.maxPasses = 128;
  o.initialPasses = 4;
  o.maxStepPerFrame = 16;
  return o;
}

// One simulated kiosk session: the controller decides, the cost model says how long the
// frame took on the virtual clock, the controller hears it. No real time anywhere.
struct Session {
  FrameRateController ctl;
  CostModel model;
  core::VirtualClock clock;
  std::vector<Decision> decisions;
  std::vector<int64_t> startNs;
  std::vector<int64_t> frameNs;
  uint32_t jitterPermille = 0;  // deterministic ± noise on the measured time

  Session(Options o, CostModel m) : ctl(std::move(o)), model(std::move(m)) {}

  void run(int frames) {
    for (int i = 0; i < frames; ++i) {
      const Decision d = ctl.next();
      const int64_t t0 = clock.nowNanoseconds();
      const uint64_t pixels = kPixelsPerPass * d.passes;
      int64_t cost = model.frameNs(
          t0, {d.passes, pixels, CostModel::uniformMapTexels(d.passes, d.shadowMapSize)});
      if (jitterPermille != 0) {
        // A counter-based hash of the frame index, never a running generator or time.
        const uint64_t h = splitmix(decisions.size());
        const int64_t span = 2 * static_cast<int64_t>(jitterPermille) + 1;
        cost += cost *
                (static_cast<int64_t>(h % static_cast<uint64_t>(span)) -
                 static_cast<int64_t>(jitterPermille)) /
                1000;
      }
      clock.advance(cost);
      ctl.report(clock.nowNanoseconds() - t0, d.passes, pixels);
      decisions.push_back(d);
      startNs.push_back(t0);
      frameNs.push_back(cost);
    }
  }

  static uint64_t splitmix(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
  }

  // Index of the first frame that started at or after `ns`.
  size_t frameAt(int64_t ns) const {
    for (size_t i = 0; i < startNs.size(); ++i) {
      if (startNs[i] >= ns) return i;
    }
    return startNs.size();
  }

  // Index of the last frame in [from, to) whose passes or map size differ from the frame
  // before it; `from` if none does.
  size_t lastChange(size_t from, size_t to) const {
    size_t last = from;
    for (size_t i = from + 1; i < to; ++i) {
      if (decisions[i].passes != decisions[i - 1].passes ||
          decisions[i].shadowMapSize != decisions[i - 1].shadowMapSize) {
        last = i;
      }
    }
    return last;
  }
};

// The most passes whose modelled cost fits the target at load `permille` (256² maps).
uint32_t bestPasses(uint32_t permille, uint32_t minP, uint32_t maxP) {
  const CostModel m(kioskCost(), {{0, permille}});
  uint32_t best = minP;
  for (uint32_t n = minP; n <= maxP; ++n) {
    if (m.frameNs(0, {n, kPixelsPerPass * n, CostModel::uniformMapTexels(n, 256)}) <= kTarget)
      best = n;
  }
  return best;
}

// A decision settled at n is acceptable if it fits and is either the best fit or inside
// the dead band [0.9 T, T].
void expectGoodSettle(const Session& s, size_t frame, uint32_t permille) {
  const Decision& d = s.decisions[frame];
  EXPECT_LE(s.frameNs[frame], kTarget) << "frame " << frame << " load " << permille;
  const bool best = d.passes == bestPasses(permille, 4, 128);
  const bool inBand = s.frameNs[frame] >= kTarget - kTarget / 10;
  EXPECT_TRUE(best || inBand) << "passes " << d.passes << " best " << bestPasses(permille, 4, 128)
                              << " load " << permille;
}

TEST(CostModel, IsTheDocumentedIntegerFormula) {
  const CostModel m({1'000, 200, 3, 7}, {{100, 1500}, {200, 500}});
  // 1000 + (2·(200·1000 + 3·64²) + 7·10) / 1000 = 1000 + 424,646 / 1000 = 1424.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64}), 1'424);
  EXPECT_EQ(m.loadPermilleAt(99), 1000u);
  EXPECT_EQ(m.loadPermilleAt(100), 1500u);
  EXPECT_EQ(m.frameNs(150, {2, 10, 2 * 64 * 64}), 1'000 + 424 * 1500 / 1000);
  EXPECT_EQ(m.frameNs(250, {2, 10, 2 * 64 * 64}), 1'000 + 424 * 500 / 1000);
  EXPECT_EQ(m.frameNs(0, {0, 0, 0}), 1'000);
  EXPECT_THROW(CostModel({-1, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(CostModel({0, 1, 0, 0}, {{5, 1000}, {5, 900}}), std::invalid_argument);
  EXPECT_THROW(CostModel({0, 1, 0, 0}, {{5, 0}}), std::invalid_argument);
}

TEST(CostModel, ChargesTheProductsVerticesPerPassPerFrameAndWhenWorkedOut) {
  // fixed 1000 ns; per pass 200 ns + 3 ps per texel + 5 ps per product vertex + 17 ps per
  // transferred vertex; 7 ps per pixel; per frame 11 ps per product vertex, 13 ps per vertex
  // shaded, 19 ps per vertex transferred.
  const CostModel m({1'000, 200, 3, 7, 5, 11, 13, 19, 17}, {{100, 2000}});
  // 2 passes of 64² with 100 vertices: 2·(200,000 + 12,288 + 500) = 425,576 ps; 10 pixels 70;
  // 100 vertices 1,100; none shaded or transferred. 426,746 ps -> 426 ns.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 0, 0}), 1'000 + 426);
  // Shaded this frame: + 1,300 ps -> 428,046 ps -> 428 ns.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 100, 0}), 1'000 + 428);
  // And transferred: + 1,900 + 2·1,700 ps -> 433,346 ps -> 433 ns.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 100, 100}), 1'000 + 433);
  // The load scales the product's part with the rest of the variable part.
  EXPECT_EQ(m.frameNs(100, {2, 10, 2 * 64 * 64, 100, 100, 100}), 1'000 + 433 * 2);
  EXPECT_THROW(CostModel({0, 0, 0, 0, 0, -1, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(CostModel({0, 0, 0, 0, 0, 0, 0, 0, -1}), std::invalid_argument);
}

TEST(CostModel, ChargesTheOccluderTrianglesThePassesDrew) {
  // The frame of the test above (426,746 ps) and 23 ps per occluder triangle drawn: a pass
  // with the fine proxy costs more than one with the coarse proxy, at the same vertex count.
  const CostModel m({1'000, 200, 3, 7, 5, 11, 13, 19, 17, 23}, {{100, 2000}});
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 0, 0, 0}), 1'000 + 426);
  // 600 coarse triangles: + 13,800 ps -> 440,546 ps -> 440 ns.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 0, 0, 600}), 1'000 + 440);
  // 5,000 fine ones: + 115,000 ps -> 541,746 ps -> 541 ns; the load scales them too.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 0, 0, 5'000}), 1'000 + 541);
  EXPECT_EQ(m.frameNs(100, {2, 10, 2 * 64 * 64, 100, 0, 0, 5'000}), 1'000 + 541 * 2);
  // Saturates at INT64_MAX picoseconds instead of wrapping to a negative cost.
  EXPECT_EQ(m.frameNs(0, {2, 10, 2 * 64 * 64, 100, 0, 0, ~uint64_t{0}}),
            1'000 + std::numeric_limits<int64_t>::max() / 1000);
  EXPECT_THROW(CostModel({0, 0, 0, 0, 0, 0, 0, 0, 0, -1}), std::invalid_argument);
}

TEST(FrameRateController, ColdStartSettlesOnTheBestFit) {
  Session s(kioskOptions(), CostModel(kioskCost()));
  s.run(300);
  const size_t settled = s.lastChange(0, 300);
  EXPECT_LE(settled, size_t{1} + (bestPasses(1000, 4, 128) - 4 + 15) / 16);
  expectGoodSettle(s, 299, 1000);
}

TEST(FrameRateController, SettlesWithinFiveFramesAfterALoadStepEitherWay) {
  // Steps up (less than the 1.5× fast-path threshold, so the bounded path is exercised) and
  // down; each held for 300 frames.
  for (uint32_t permille : {1100u, 1200u, 1400u, 900u, 800u, 600u, 500u}) {
    SCOPED_TRACE("load " + std::to_string(permille));
    const int64_t stepAt = 100 * kTarget;
    Session s(kioskOptions(), CostModel(kioskCost(), {{stepAt, permille}}));
    s.run(400);
    const size_t k = s.frameAt(stepAt);
    ASSERT_LT(k, 150u);
    ASSERT_LE(s.lastChange(0, k) + 50, k) << "not settled before the step";
    expectGoodSettle(s, k - 1, 1000);
    const size_t settled = s.lastChange(k, s.decisions.size());
    EXPECT_LE(settled, k + 5);
    ASSERT_GE(s.decisions.size() - settled, 200u);
    // No oscillation: constant for the remaining (≥ 200) frames.
    for (size_t i = settled; i < s.decisions.size(); ++i) {
      ASSERT_EQ(s.decisions[i].passes, s.decisions[settled].passes) << "frame " << i;
    }
    expectGoodSettle(s, s.decisions.size() - 1, permille);
  }
}

TEST(FrameRateController, NoOscillationWhenTheFixedCostIsUnderestimated) {
  // Proof sketch in the header: with F̂ < F the iteration is monotone; the answer is still
  // the true best fit because the fixed point of t(n) = T does not depend on F̂.
  for (int64_t fixedGuess : {int64_t{0}, kFixed / 2, kFixed - 1}) {
    Options o = kioskOptions();
    o.fixedCostNs = fixedGuess;
    Session s(o, CostModel(kioskCost(), {{100 * kTarget, 700}}));
    s.run(450);
    const size_t k = s.frameAt(100 * kTarget);
    for (size_t from : {size_t{0}, k}) {
      const size_t to = from == 0 ? k : s.decisions.size();
      // Within each constant-cost stretch passes move one way only.
      int direction = 0;
      for (size_t i = from + 1; i < to; ++i) {
        const int64_t delta = static_cast<int64_t>(s.decisions[i].passes) -
                              static_cast<int64_t>(s.decisions[i - 1].passes);
        if (delta == 0) continue;
        const int sign = delta > 0 ? 1 : -1;
        if (direction == 0) direction = sign;
        ASSERT_EQ(sign, direction) << "reversal at frame " << i << " fixed guess " << fixedGuess;
      }
    }
    const size_t settled = s.lastChange(k, s.decisions.size());
    EXPECT_GE(s.decisions.size() - settled, 200u) << "fixed guess " << fixedGuess;
    expectGoodSettle(s, s.decisions.size() - 1, 700);
  }
}

TEST(FrameRateController, DoubleCostOverrunDropsPassesWithinTwoFrames) {
  const int64_t stepAt = 60 * kTarget;
  Session s(kioskOptions(), CostModel(kioskCost(), {{stepAt, 2000}}));
  s.run(300);
  const size_t k = s.frameAt(stepAt);
  const uint32_t before = s.decisions[k].passes;
  ASSERT_GT(s.frameNs[k], kTarget + kTarget / 2) << "the step must overrun by > 50%";
  // Frame k overran; frame k+1 is already cut, without the step bound, and fits.
  EXPECT_LT(s.decisions[k + 1].passes, before);
  EXPECT_TRUE(s.decisions[k + 1].fastDrop);
  EXPECT_GT(before - s.decisions[k + 1].passes, kioskOptions().maxStepPerFrame);
  EXPECT_LE(s.frameNs[k + 1], kTarget);
  EXPECT_LE(s.frameNs[k + 2], kTarget);
  EXPECT_EQ(s.lastChange(k, 300), k + 1);
}

TEST(FrameRateController, OverrunWithUnderestimatedFixedCostFitsWithinTwoFrames) {
  Options o = kioskOptions();
  o.fixedCostNs = kFixed / 2;
  const int64_t stepAt = 60 * kTarget;
  Session s(o, CostModel(kioskCost(), {{stepAt, 2000}}));
  s.run(200);
  const size_t k = s.frameAt(stepAt);
  EXPECT_LT(s.decisions[k + 1].passes, s.decisions[k].passes);
  EXPECT_LE(s.frameNs[k + 2], kTarget);
}

TEST(FrameRateController, ChangePerFrameIsBoundedOutsideTheFastPath) {
  // A scripted wander of the load below the 1.5× overrun threshold, with measurement noise.
  std::vector<CostModel::LoadStep> steps;
  for (int i = 1; i < 40; ++i) {
    steps.push_back(
        {i * 25 * kTarget,
         static_cast<uint32_t>(700 + Session::splitmix(static_cast<uint64_t>(i)) % 500)});
  }
  Options o = kioskOptions();
  o.maxStepPerFrame = 5;
  Session s(o, CostModel(kioskCost(), steps));
  s.jitterPermille = 30;
  s.run(1200);
  for (size_t i = 1; i < s.decisions.size(); ++i) {
    const uint32_t a = s.decisions[i - 1].passes, b = s.decisions[i].passes;
    const uint32_t change = a > b ? a - b : b - a;
    if (!s.decisions[i].fastDrop) {
      ASSERT_LE(change, 5u) << "frame " << i;
    } else {
      ASSERT_GT(s.frameNs[i - 1], kTarget + kTarget / 2) << "fast drop without overrun";
      ASSERT_LT(b, a);
    }
  }
}

TEST(FrameRateController, MinAndMaxPassesAreRespected) {
  // Cheap scene: wants far more than max. Expensive: less than min (no ladder here).
  for (uint32_t permille : {50u, 1000u, 20'000u}) {
    Options o = kioskOptions();
    o.minPasses = 6;
    o.maxPasses = 40;
    o.initialPasses = 20;
    Session s(o, CostModel(kioskCost(), {{0, permille}}));
    s.run(100);
    for (const Decision& d : s.decisions) {
      ASSERT_GE(d.passes, 6u);
      ASSERT_LE(d.passes, 40u);
      ASSERT_EQ(d.shadowMapSize, 256u);
    }
    if (permille == 50) {
      EXPECT_EQ(s.decisions.back().passes, 40u);
    }
    if (permille == 20'000) {
      EXPECT_EQ(s.decisions.back().passes, 6u);
      EXPECT_TRUE(s.decisions.back().overBudget);
    }
  }
}

TEST(FrameRateController, ShadowMapLadderEngagesOnlyAtMinPasses) {
  Options o = kioskOptions();
  o.minPasses = 8;
  o.initialPasses = 40;
  o.shadowMapSizes = {256, 128, 64};
  // Per-pass cost dominated by the map: 0.1 ms + 65,536 texels × 60 ns + 0.15 ms ≈ 4.2 ms
  // at 256², ≈ 1.2 ms at 128².
  const CostModel::Params heavyMaps{kFixed, 100'000, 60'000, 50'000};
  // Nominal: fits ~14 passes at 256². ×3: 8 passes at 256² no longer fit, at 128² they do.
  // Back to ×1: the 256² map returns, then passes grow again.
  Session s(o, CostModel(heavyMaps, {{100 * kTarget, 3000}, {250 * kTarget, 1000}}));
  s.run(400);
  bool laddered = false;
  for (size_t i = 0; i < s.decisions.size(); ++i) {
    const Decision& d = s.decisions[i];
    if (d.shadowMapSize != 256) {
      laddered = true;
      ASSERT_EQ(d.passes, o.minPasses) << "frame " << i;
    }
    // The map shrinks only once passes are at min: already there the frame before, or
    // dropped there in the same decision by the > 50% overrun fast path.
    if (i > 0 && d.shadowMapSize < s.decisions[i - 1].shadowMapSize) {
      ASSERT_TRUE(s.decisions[i - 1].passes == o.minPasses || d.fastDrop)
          << "map shrank above min, frame " << i;
    }
  }
  EXPECT_TRUE(laddered);
  const size_t up = s.frameAt(100 * kTarget), down = s.frameAt(250 * kTarget);
  // Under the heavy load it settles on a smaller map, fits, and stays (no ping-pong).
  const size_t settledHeavy = s.lastChange(up, down);
  EXPECT_LE(settledHeavy, up + 5);
  EXPECT_LT(s.decisions[down - 1].shadowMapSize, 256u);
  EXPECT_EQ(s.decisions[down - 1].passes, 8u);
  EXPECT_LE(s.frameNs[down - 1], kTarget);
  // Load back to nominal: full-size maps again and more passes than the minimum.
  const size_t settledLight = s.lastChange(down, s.decisions.size());
  EXPECT_LE(settledLight, down + 5);
  EXPECT_EQ(s.decisions.back().shadowMapSize, 256u);
  EXPECT_GT(s.decisions.back().passes, 8u);
  EXPECT_LE(s.frameNs.back(), kTarget);
}

TEST(FrameRateController, ReplayGivesTheIdenticalDecisionSequence) {
  std::vector<CostModel::LoadStep> steps = {
      {40 * kTarget, 1300}, {90 * kTarget, 2500}, {150 * kTarget, 600}, {220 * kTarget, 1000}};
  Options o = kioskOptions();
  o.shadowMapSizes = {256, 128};
  auto session = [&] {
    Session s(o, CostModel(kioskCost(), steps));
    s.jitterPermille = 40;
    s.run(400);
    return s;
  };
  Session a = session(), b = session();
  ASSERT_EQ(a.decisions.size(), b.decisions.size());
  for (size_t i = 0; i < a.decisions.size(); ++i) {
    ASSERT_EQ(a.decisions[i].passes, b.decisions[i].passes) << i;
    ASSERT_EQ(a.decisions[i].shadowMapSize, b.decisions[i].shadowMapSize) << i;
    ASSERT_EQ(a.decisions[i].predictedFrameNs, b.decisions[i].predictedFrameNs) << i;
    ASSERT_EQ(a.decisions[i].fastDrop, b.decisions[i].fastDrop) << i;
    ASSERT_EQ(a.frameNs[i], b.frameNs[i]) << i;
  }
  EXPECT_EQ(a.clock.nowNanoseconds(), b.clock.nowNanoseconds());
}

TEST(FrameRateController, NoiseInsideTheDeadBandDoesNotMovePasses) {
  Session s(kioskOptions(), CostModel(kioskCost()));
  s.jitterPermille = 20;  // ±2% measured-time noise
  s.run(400);
  int changes = 0;
  for (size_t i = 101; i < s.decisions.size(); ++i) {
    changes += s.decisions[i].passes != s.decisions[i - 1].passes;
  }
  EXPECT_LE(changes, 4) << "popping under noise";
}

TEST(FrameRateController, NextIsStableUntilTheNextReport) {
  FrameRateController c(kioskOptions());
  const Decision first = c.next();
  EXPECT_EQ(first.passes, 4u);
  EXPECT_EQ(first.predictedFrameNs, -1);
  c.report(kFixed + 4 * 1'000'000, 4, 0);
  const Decision a = c.next(), b = c.next();
  EXPECT_EQ(a.passes, b.passes);
  EXPECT_EQ(a.passes, 20u);  // 4 + maxStep 16 toward floor(56.67 ms / 1 ms) = 56
  EXPECT_EQ(c.perPassEstimateQ8(), 1'000'000 * 256);
}

// The kiosk of data/sessions/*.json at 30 fps on the simulated board: fixed 7 ms (F̂ 6 ms),
// 2 ns per shadow-map texel and 14 ns per shadowed pixel, maps 256² → 128² → 64².
Options boardOptions() {
  Options o;
  o.targetFrameNs = 33'333'333;
  o.fixedCostNs = 6'000'000;
  o.minPasses = 4;
  o.maxPasses = 64;
  o.initialPasses = 8;
  o.shadowMapSizes = {256, 128, 64};
  return o;
}
CostModel::Params boardCost() {
  return {7'000'000, 0, 2'000, 14'000};
}

// Frames from the first frame starting at `fromNs` until the controller is back where it was
// before the overload: the largest map and at least the passes of the frame before `atNs`
// (the settled pre-overload choice). SIZE_MAX if never.
size_t framesToRecover(const Session& s, int64_t beforeNs, int64_t fromNs) {
  const Decision& before = s.decisions[s.frameAt(beforeNs) - 1];
  for (size_t i = s.frameAt(fromNs); i < s.decisions.size(); ++i) {
    if (s.decisions[i].shadowMapSize == before.shadowMapSize &&
        s.decisions[i].passes >= before.passes) {
      return i - s.frameAt(fromNs);
    }
  }
  return SIZE_MAX;
}

TEST(FrameRateController, RecoversFromALongHeavyOverload) {
  // Issue 18: 100× load from 2 s to 6 s, then nominal for 26 s. The larger maps' cost must
  // not be remembered from the overload: back on 256² and the pre-overload passes promptly.
  constexpr int64_t kS = 1'000'000'000;
  for (const auto& [permille, endNs] : {std::pair{100'000u, 6 * kS}, std::pair{20'000u, 3 * kS}}) {
    SCOPED_TRACE("load " + std::to_string(permille) + " until " + std::to_string(endNs / kS) +
                 " s");
    Session s(boardOptions(), CostModel(boardCost(), {{2 * kS, permille}, {endNs, 1000}}));
    s.run(960);
    // The overload did engage the ladder, down to 64² (the situation of the issue).
    uint32_t smallest = 256;
    for (size_t i = s.frameAt(2 * kS); i < s.frameAt(endNs); ++i) {
      smallest = std::min(smallest, s.decisions[i].shadowMapSize);
    }
    ASSERT_EQ(smallest, permille == 100'000u ? 64u : 256u);
    const size_t recover = framesToRecover(s, 2 * kS, endNs);
    std::printf("[ measured ] load %u‰ until %lld s: back to %u passes at 256² after %zu frames\n",
                permille, static_cast<long long>(endNs / kS),
                s.decisions[s.frameAt(2 * kS) - 1].passes, recover);
    // Two crossings up (two frames each) plus passes growing 4 → 64 by ≤ 8 a frame.
    EXPECT_LE(recover, 2 * 2 + (64 - 4 + 7) / 8 + 2);
    // And it stays there: no probe or ping-pong under the now steady load.
    const size_t settled = s.lastChange(s.frameAt(endNs), s.decisions.size());
    EXPECT_LT(settled, s.frameAt(endNs) + 30);
    EXPECT_EQ(s.decisions.back().shadowMapSize, 256u);
  }
}

// A one-frame spike exactly on a map change corrupts the ratio measured there (the larger
// map looks far dearer than it is). It must still recover within the stated bound: the
// estimate expires after probeAfterFrames and a probe re-measures it.
TEST(FrameRateController, RecoversWithinTheBoundFromAnyOverload) {
  constexpr int64_t kS = 1'000'000'000;
  Options o = boardOptions();
  o.probeAfterFrames = 90;
  o.maxProbeAfterFrames = 360;
  // Every schedule: a random heavy load for a random time, ended by nominal load; the bound
  // of the .h is P_max + R·(settle + 1) frames for the map, then passes regrow.
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    const uint64_t h = Session::splitmix(seed);
    const uint32_t permille = 2'000 + static_cast<uint32_t>(h % 150'000);
    const int64_t startNs = kS / 2 + static_cast<int64_t>((h >> 20) % 1000) * kS / 1000;
    const int64_t endNs = startNs + kS / 10 + static_cast<int64_t>((h >> 32) % 8000) * kS / 1000;
    SCOPED_TRACE("seed " + std::to_string(seed) + " load " + std::to_string(permille));
    Session s(o, CostModel(boardCost(), {{startNs, permille}, {endNs, 1000}}));
    s.jitterPermille = static_cast<uint32_t>(h % 3) * 10;  // 0, ±1 %, ±2 % noise
    s.run(static_cast<int>(endNs / (kS / 30)) + 600);
    const size_t bound = 360 + 3 * 8 + (64 - 4 + 7) / 8 + 2;
    EXPECT_LE(framesToRecover(s, startNs, endNs), bound);
  }
}

TEST(FrameRateController, ASpikeOnAMapChangeIsProbedAwayInBoundedTime) {
  // A heavy scene (33× the board's nominal pass cost): 4 passes at 256² just fit the band,
  // at 128² they cost about 0.43× as much. One frame 10× dearer still (a kernel hiccup) at
  // 256² drops the map; the next frame, at 128², is normal again, so the crossing measures
  // the larger map as ≥ 4× dearer (clamped to the texel ratio), and the prediction alone
  // would keep 128² for ever.
  Options o = boardOptions();
  o.probeAfterFrames = 90;
  o.maxProbeAfterFrames = 360;
  o.minPasses = o.maxPasses = o.initialPasses = 4;
  const CostModel heavy(boardCost(), {{0, 33'000}});
  FrameRateController c(o);
  std::vector<Decision> d;
  for (int i = 0; i < 1000; ++i) {
    d.push_back(c.next());
    int64_t ns =
        heavy.frameNs(0, {4, 4 * 3'000, CostModel::uniformMapTexels(4, d.back().shadowMapSize)});
    if (i == 10) ns *= 10;
    c.report(ns, 4, 0);
  }
  ASSERT_EQ(d[10].shadowMapSize, 256u);
  ASSERT_EQ(d[11].shadowMapSize, 128u) << "the spike did not move the map";
  EXPECT_EQ(d[12].shadowMapSize, 128u) << "the prediction alone should not climb back";
  size_t back = 11;
  while (back < d.size() && d[back].shadowMapSize != 256) ++back;
  // Measured at 128² from frame 12: the ratio expires 90 frames after it was measured.
  EXPECT_LE(back, size_t{12 + 90 + 1}) << "not back on 256² within probeAfterFrames";
  // The probe held (256² fits): no further map change.
  for (size_t i = back; i < d.size(); ++i) ASSERT_EQ(d[i].shadowMapSize, 256u) << i;
}

TEST(FrameRateController, UnderASteadyHeavyLoadProbesAreRareAndBackOff) {
  // 60× for the whole session: 4 passes at 256² never fit (48 ms), at 128² they do (25 ms). The
  // only moves after settling are probes, one frame each, spaced ≥ P_r which doubles to P_max.
  Options o = boardOptions();
  o.probeAfterFrames = 100;
  o.maxProbeAfterFrames = 400;
  Session s(o, CostModel(boardCost(), {{0, 60'000}}));
  s.run(3000);
  std::vector<size_t> ups;  // frames where the map grew
  for (size_t i = 1; i < s.decisions.size(); ++i) {
    if (s.decisions[i].shadowMapSize > s.decisions[i - 1].shadowMapSize) ups.push_back(i);
    EXPECT_EQ(s.decisions[i].passes, 4u) << i;
  }
  const size_t settled = 10;
  size_t lastUp = 0, probes = 0;
  for (size_t up : ups) {
    if (up < settled) continue;
    ++probes;
    // A failed probe goes straight back down the next frame.
    ASSERT_LT(s.decisions[up + 1].shadowMapSize, s.decisions[up].shadowMapSize) << up;
    if (lastUp != 0) {
      EXPECT_GE(up - lastUp, 100u);
    }
    lastUp = up;
  }
  // 3000 frames: at most ~100 + 200 + 400 + 400·k probe spacing → ≤ 9 probes.
  EXPECT_LE(probes, 9u);
  EXPECT_GE(probes, 1u) << "the bound needs the probe";
  // Every frame but the probes fits the target (the dead band holds between them).
  for (size_t i = 200; i < s.decisions.size(); ++i) {
    if (std::find(ups.begin(), ups.end(), i) != ups.end()) continue;
    ASSERT_LE(s.frameNs[i], o.targetFrameNs) << i;
  }
}

void expectThrowsWith(const Options& o, const std::string& needle) {
  try {
    FrameRateController c(o);
    ADD_FAILURE() << "no throw for " << needle;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(FrameRateController, GarbageOptionsThrowWithClearMessages) {
  Options o = kioskOptions();
  o.targetFrameNs = 0;
  expectThrowsWith(o, "targetFrameNs must be > 0 (got 0)");
  o.targetFrameNs = -5;
  expectThrowsWith(o, "targetFrameNs must be > 0 (got -5)");
  o = kioskOptions();
  o.minPasses = 10;
  o.maxPasses = 9;
  expectThrowsWith(o, "minPasses (10) must be <= maxPasses (9)");
  o = kioskOptions();
  o.minPasses = 0;
  expectThrowsWith(o, "minPasses must be >= 1");
  o = kioskOptions();
  o.fixedCostNs = kTarget;
  expectThrowsWith(o, "fixedCostNs must be in [0, targetFrameNs)");
  o = kioskOptions();
  o.maxStepPerFrame = 0;
  expectThrowsWith(o, "maxStepPerFrame");
  o = kioskOptions();
  o.hysteresis = {1, 1};
  expectThrowsWith(o, "hysteresis must be < 1");
  o = kioskOptions();
  o.smoothing = {0, 4};
  expectThrowsWith(o, "smoothing must be in (0, 1]");
  o = kioskOptions();
  o.smoothing = {1, 0};
  expectThrowsWith(o, "smoothing must be num/den");
  o = kioskOptions();
  o.shadowMapSizes = {128, 256};
  expectThrowsWith(o, "strictly decreasing");
  o = kioskOptions();
  o.shadowMapSizes = {};
  expectThrowsWith(o, "shadowMapSizes");
  o = kioskOptions();
  o.initialPasses = 200;
  expectThrowsWith(o, "initialPasses (200)");
  o = kioskOptions();
  o.probeAfterFrames = 0;
  expectThrowsWith(o, "probeAfterFrames must be >= 1");
  o = kioskOptions();
  o.maxProbeAfterFrames = 10;
  expectThrowsWith(o, "maxProbeAfterFrames (10) must be >= probeAfterFrames (300)");

  FrameRateController c(kioskOptions());
  EXPECT_THROW(c.report(-1, 4, 0), std::invalid_argument);
  EXPECT_THROW(c.report(1, 70'000, 0), std::invalid_argument);
  EXPECT_NO_THROW(c.report(0, 0, 0));  // an empty frame is legal and teaches nothing
  EXPECT_EQ(c.perPassEstimateQ8(), 0);
}

}  // namespace
}  // namespace penumbra::shadow
