#include "shadow/frame_rate_controller.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace penumbra::shadow {
namespace {

// Overflow bounds (why every product below fits in int64, max ≈ 9.22e18):
//   T ≤ kMaxTargetFrameNs = 1e10, and a measured frame is clamped to ≤ 16·T = 1.6e11 ns,
//   so a sample s = (t − F̂)·256/n ≤ 4.1e13 and p̂, a convex combination or maximum of
//   samples, obeys the same bound. Then n·p̂ ≤ 65,536 · 4.1e13 ≈ 2.7e18; |s − p̂|·num and
//   p̂·num with num ≤ 65,536 are ≤ 2.7e18; T·256 ≤ 2.6e12 and T·num ≤ 6.6e14.
// The one product that can exceed int64 (p̂ · p̂ in the ladder's rescaling) goes through
// mulDiv's 128-bit intermediate.
constexpr int kFracBits = 8;  // p̂ in ns·2^-8: sub-ns resolution for ~µs passes
constexpr int64_t kOne = int64_t{1} << kFracBits;
constexpr int64_t kOverrunClamp = 16;  // measured frames count as at most 16·T

__extension__ typedef __int128 Int128;  // GCC/Clang; __extension__ keeps -Wpedantic quiet

// floor(a·b/c) for a, b ≥ 0, c > 0, saturated to INT64_MAX.
int64_t mulDiv(int64_t a, int64_t b, int64_t c) {
  const Int128 q = static_cast<Int128>(a) * b / c;
  return q > std::numeric_limits<int64_t>::max() ? std::numeric_limits<int64_t>::max()
                                                 : static_cast<int64_t>(q);
}

void checkRatio(const FrameRateController::Ratio& r, const char* name) {
  if (r.den == 0 || r.den > FrameRateController::kMaxRatioDen ||
      r.num > FrameRateController::kMaxRatioDen) {
    throw std::invalid_argument(std::string("FrameRateController: ") + name +
                                " must be num/den with 0 < den <= 65536 and num <= 65536 (got " +
                                std::to_string(r.num) + "/" + std::to_string(r.den) + ")");
  }
}

[[noreturn]] void bad(const std::string& what) {
  throw std::invalid_argument("FrameRateController: " + what);
}

FrameRateController::Options validated(FrameRateController::Options o) {
  using C = FrameRateController;
  if (o.targetFrameNs <= 0) {
    bad("targetFrameNs must be > 0 (got " + std::to_string(o.targetFrameNs) + ")");
  }
  if (o.targetFrameNs > C::kMaxTargetFrameNs) {
    bad("targetFrameNs must be <= 10 s (got " + std::to_string(o.targetFrameNs) + " ns)");
  }
  if (o.fixedCostNs < 0 || o.fixedCostNs >= o.targetFrameNs) {
    bad("fixedCostNs must be in [0, targetFrameNs) (got " + std::to_string(o.fixedCostNs) +
        " with target " + std::to_string(o.targetFrameNs) + "): no pass would ever fit");
  }
  if (o.minPasses == 0) bad("minPasses must be >= 1 (per-pass cost is measured per pass)");
  if (o.minPasses > o.maxPasses) {
    bad("minPasses (" + std::to_string(o.minPasses) + ") must be <= maxPasses (" +
        std::to_string(o.maxPasses) + ")");
  }
  if (o.maxPasses > C::kMaxPassesLimit) {
    bad("maxPasses must be <= 65536 (got " + std::to_string(o.maxPasses) + ")");
  }
  if (o.initialPasses != 0 && (o.initialPasses < o.minPasses || o.initialPasses > o.maxPasses)) {
    bad("initialPasses (" + std::to_string(o.initialPasses) + ") must be 0 or in [minPasses, " +
        "maxPasses]");
  }
  if (o.maxStepPerFrame == 0) bad("maxStepPerFrame must be >= 1 (or passes could never move)");
  checkRatio(o.hysteresis, "hysteresis");
  checkRatio(o.smoothing, "smoothing");
  checkRatio(o.stepDetect, "stepDetect");
  if (o.hysteresis.num >= o.hysteresis.den) bad("hysteresis must be < 1");
  if (o.smoothing.num == 0 || o.smoothing.num > o.smoothing.den) {
    bad("smoothing must be in (0, 1] (got " + std::to_string(o.smoothing.num) + "/" +
        std::to_string(o.smoothing.den) + ")");
  }
  if (o.probeAfterFrames == 0) bad("probeAfterFrames must be >= 1");
  if (o.maxProbeAfterFrames < o.probeAfterFrames) {
    bad("maxProbeAfterFrames (" + std::to_string(o.maxProbeAfterFrames) +
        ") must be >= probeAfterFrames (" + std::to_string(o.probeAfterFrames) + ")");
  }
  if (o.shadowMapSizes.empty()) bad("shadowMapSizes must hold at least one size");
  for (size_t i = 0; i < o.shadowMapSizes.size(); ++i) {
    if (o.shadowMapSizes[i] == 0) bad("shadowMapSizes must be > 0");
    if (i > 0 && o.shadowMapSizes[i] >= o.shadowMapSizes[i - 1]) {
      bad("shadowMapSizes must be strictly decreasing (largest first)");
    }
  }
  return o;
}

}  // namespace

FrameRateController::FrameRateController(Options options)
    : options_(validated(std::move(options))),
      passes_(options_.initialPasses != 0 ? options_.initialPasses : options_.minPasses),
      ratioQ8_(options_.shadowMapSizes.size(), 0),
      ratioFrame_(options_.shadowMapSizes.size(), 0),
      probeAfter_(options_.shadowMapSizes.size(), options_.probeAfterFrames) {}

int64_t FrameRateController::predictedQ8(uint32_t passes, int64_t perPassQ8) const {
  return options_.fixedCostNs * kOne + static_cast<int64_t>(passes) * perPassQ8;
}

void FrameRateController::report(int64_t frameNs, uint32_t passes, uint64_t shadowedPixels) {
  if (frameNs < 0) {
    throw std::invalid_argument("FrameRateController::report: frameNs must be >= 0 (got " +
                                std::to_string(frameNs) + ")");
  }
  if (passes > kMaxPassesLimit) {
    throw std::invalid_argument("FrameRateController::report: passes must be <= 65536 (got " +
                                std::to_string(passes) + ")");
  }
  decided_ = false;
  lastShadowedPixels_ = shadowedPixels;
  const int64_t target = options_.targetFrameNs;
  const int64_t t = std::min(frameNs, kOverrunClamp * target);
  overran_ = t > target + target / 2;
  if (passes == 0) return;  // says nothing about the cost of a pass
  ++frames_;

  const int64_t excess = std::max<int64_t>(t - options_.fixedCostNs, 0);
  const int64_t s = std::max<int64_t>(excess * kOne / passes, 1);
  if (perPassQ8_ == 0 || resetEstimate_) {
    if (resetEstimate_) measureRatio(s);
    perPassQ8_ = s;
    resetEstimate_ = false;
    return;
  }
  const int64_t d = s - perPassQ8_;
  const int64_t absD = d < 0 ? -d : d;
  // A missed deadline is not noise to average away: the estimate never stays below what
  // the overrunning frame measured (this is what makes the fast path fit, and it stops a
  // slow EMA from overrunning frame after frame). It moves p̂ toward s without passing it,
  // so proof step 1 in the .h still holds.
  const bool missedDeadline = t > target && s > perPassQ8_;
  // A load step: follow it now instead of over ~log(1/w) frames.
  const bool loadStep = absD * options_.stepDetect.den > perPassQ8_ * options_.stepDetect.num;
  if (missedDeadline || loadStep) {
    perPassQ8_ = s;
  } else {
    // EMA p̂ += w·(s − p̂), truncated toward zero but by at least one unit, so p̂ reaches s
    // exactly and never overshoots it (|step| ≤ |d| because w ≤ 1): proof step 1 in the .h.
    int64_t step = d * options_.smoothing.num / options_.smoothing.den;
    if (step == 0) step = d > 0 ? 1 : (d < 0 ? -1 : 0);
    perPassQ8_ += step;
  }
}

void FrameRateController::measureRatio(int64_t firstSampleQ8) {
  // The crossing's two adjacent frames: the last p̂ at the rung left and the first sample at
  // the rung entered. ρ = larger map / smaller map, clamped to [1, texel ratio] (see the .h).
  const size_t boundary = std::max(rung_, crossedFrom_);
  const bool down = crossedFrom_ < rung_;
  const int64_t largerQ8 = down ? crossedFromQ8_ : firstSampleQ8;
  const int64_t smallerQ8 = down ? firstSampleQ8 : crossedFromQ8_;
  const int64_t big = options_.shadowMapSizes[boundary - 1];
  const int64_t small = options_.shadowMapSizes[boundary];
  const int64_t maxRatioQ8 = mulDiv(big * big, kOne, small * small);
  ratioQ8_[boundary] = std::clamp<int64_t>(mulDiv(largerQ8, kOne, std::max<int64_t>(smallerQ8, 1)),
                                           kOne, maxRatioQ8);
  ratioFrame_[boundary] = frames_;
  probeArrived_ = probing_;
  probing_ = false;
}

FrameRateController::Decision FrameRateController::next() {
  if (decided_) return decision_;
  decided_ = true;
  const auto& sizes = options_.shadowMapSizes;
  Decision out;
  if (perPassQ8_ == 0 || resetEstimate_) {
    // Nothing measured yet (at this map size): keep the current choice.
    out.passes = passes_;
    out.shadowMapSize = sizes[rung_];
    decision_ = out;
    return out;
  }

  const int64_t target = options_.targetFrameNs;
  const int64_t budgetQ8 = (target - options_.fixedCostNs) * kOne;
  const int64_t targetQ8 = target * kOne;
  const int64_t lowQ8 =
      (target - target * options_.hysteresis.num / options_.hysteresis.den) * kOne;
  const uint32_t minP = options_.minPasses;
  const uint32_t maxP = options_.maxPasses;
  const bool minFits = predictedQ8(minP, perPassQ8_) <= targetQ8;

  uint32_t n = passes_;
  size_t rung = rung_;
  bool probe = false;
  // A probe measured at its first frame (a failed one goes straight back down below).
  const bool judgeProbe = probeArrived_;
  probeArrived_ = false;
  if (rung > 0) {
    // Reduced map: passes are pinned at min; only the map size moves.
    n = minP;
    if (!minFits) {
      if (rung + 1 < sizes.size()) ++rung;
    } else {
      // The larger map costs ρ·p̂ per pass; an expired ρ counts as 1, its optimistic bound,
      // so a wrong estimate is re-measured by a probe within P_r frames (the bound in the .h).
      const bool expired = ratioQ8_[rung] == 0 || frames_ - ratioFrame_[rung] >= probeAfter_[rung];
      const int64_t ratioQ8 = expired ? kOne : ratioQ8_[rung];
      const int64_t upQ8 = std::max<int64_t>(mulDiv(perPassQ8_, ratioQ8, kOne), 1);
      if (predictedQ8(minP, upQ8) <= lowQ8) {
        --rung;
        probe = expired;
      }
    }
  } else {
    const int64_t nStar = budgetQ8 / perPassQ8_;  // floor(B / p̂)
    const uint32_t tgt =
        static_cast<uint32_t>(std::clamp<int64_t>(nStar, static_cast<int64_t>(minP), maxP));
    const int64_t keepQ8 = predictedQ8(n, perPassQ8_);
    const bool inBand = keepQ8 >= lowQ8 && keepQ8 <= targetQ8;
    if (!inBand && tgt != n) {
      if (overran_ && tgt < n) {
        n = tgt;
        out.fastDrop = true;
      } else if (tgt > n) {
        n = n + std::min(options_.maxStepPerFrame, tgt - n);
      } else {
        n = n - std::min(options_.maxStepPerFrame, n - tgt);
      }
    }
    // The ladder engages only at min passes: already there, or dropped there by the fast
    // path (a frame that overran by half cannot wait a frame for the map to shrink).
    if (n == minP && (passes_ == minP || out.fastDrop) && !minFits && sizes.size() > 1) {
      rung = 1;
    }
  }

  if (judgeProbe) {
    // Failed: back down, and the next probe of this boundary waits twice as long (≤ P_max).
    // Held: the expiry returns to its start.
    uint32_t& after = probeAfter_[rung_ + 1];
    after = rung > rung_ ? static_cast<uint32_t>(std::min<uint64_t>(uint64_t{after} * 2,
                                                                    options_.maxProbeAfterFrames))
                         : options_.probeAfterFrames;
  }
  if (rung != rung_) {
    crossedFrom_ = rung_;
    crossedFromQ8_ = perPassQ8_;
    probing_ = probe;
    rung_ = rung;
    resetEstimate_ = true;  // the pass cost at the new size is unknown until measured
  }
  passes_ = n;
  out.passes = n;
  out.shadowMapSize = sizes[rung_];
  if (!resetEstimate_) out.predictedFrameNs = predictedQ8(n, perPassQ8_) / kOne;
  out.overBudget = rung_ + 1 == sizes.size() && n == minP && !minFits && !resetEstimate_;
  decision_ = out;
  return out;
}

}  // namespace penumbra::shadow
