// Frame-rate control by the number of source clusters (Gibson 2003 §8; design.md §1 step 5
// and step 8): before each frame choose n, the number of shadow blending passes (and, once
// n is at its floor, the shadow-map size); after the frame, feed back its measured time.
//
// Cost model (Gibson 2003 §9, Fig. 9: 10/20/50 passes at 35/25/14 fps, i.e. time roughly
// affine in passes): t(n) = F + p·n, F the fixed part (camera frame, shading, depth
// composite), p the cost of one pass (shadow-map render + masked subtraction over the
// receiver pixels, so pass cost already includes the shadowed-pixel work).
//
// CONTROL LAW. F̂ = Options::fixedCostNs is given (measure it as the time of a zero-pass
// frame); p̂ is estimated from each report as s = (t − F̂)/n in Q8 fixed point and smoothed
// by an integer EMA with weight w (a deviation > stepDetect·p̂ is taken as a load step and
// replaces p̂; a frame that overran T raises p̂ to at least s: a missed deadline is never
// averaged away). Before each frame, with budget B = T − F̂ and target
// n* = clamp(floor(B/p̂), min, max):
//   - keep n while the predicted cost F̂ + n·p̂ lies in the dead band [T·(1−h), T];
//   - otherwise move n toward n* by at most maxStepPerFrame, never past it;
//   - fast path: if the last frame took > 1.5·T, jump straight down to n* (no step bound);
//   - ladder: only with n = min and F̂ + min·p̂ > T, step to the next smaller map; climb back a
//     rung only if the larger map is predicted to cost ≤ T·(1−h) at min passes. Passes stay
//     at min while any rung below the first is in use.
//
// THE LARGER MAP'S COST (ladder, climbing back). A load change scales the pass cost of every
// map size alike (it is the scene that got heavier), so what carries over from one size to
// the next is their RATIO ρ_r = p(size_{r−1}) / p(size_r), not either cost. ρ_r is measured
// at every crossing of the boundary r, in either direction, from the last p̂ at the rung left
// and the first sample at the rung entered (two adjacent frames, so one load), and clamped
// to [1, (size_{r−1}/size_r)²]: a larger map never costs less per pass, and at most its
// texel count more (pass = shadow-map render + masked subtraction, Gibson 2003 §8). The
// larger map is predicted to cost ρ_r·p̂ per pass. (Keeping the larger map's absolute cost
// from the moment it was left, as an earlier version did, kept an overload's cost forever:
// after a 4 s 100× load the kiosk stayed at 128² and 4 passes for the rest of the session.)
//
// WHY IT ALWAYS RECOVERS (the bound). ρ_r can still be wrong: a one-frame spike or a load
// change that falls exactly between the two frames of a crossing. A wrong-high ρ_r would keep
// the small map forever, so an estimate EXPIRES: ρ_r measured more than P_r frames ago
// counts as 1, its optimistic bound, and the controller climbs (probes) as soon as the
// larger map at ratio 1 is predicted to fit the band — i.e. whenever it could possibly fit.
// A probe measures ρ_r afresh (a failed probe measures it twice, going up and coming back,
// and costs one frame over budget). P_r starts at Options::probeAfterFrames, doubles after
// each failed probe up to Options::maxProbeAfterFrames (P_max) and returns to the start
// after a climb that holds. Frames are counted as reports with passes > 0 (a frame without
// passes tells nothing about their cost, and costs none). Proof sketch: let the load settle
// at frame f0 at a level where the larger maps truly fit the band at min passes. Ages run
// for all boundaries at once, so by f0 + P_max every ratio was either measured after f0
// (two adjacent frames at the settled load: exact) or has expired and counts as 1 ≤ the
// true ratio; either way the prediction for the larger map is ≤ its true cost, so the condition
// to climb holds at the first decision where the current rung's p̂ has settled (≤ the
// EMA's finite settling time of proof step 1 below, and at once after a load step since a
// step replaces p̂). Each climb is then measured to fit and is kept, so with R rungs the
// kiosk is back on the largest map within P_max + R·(settle + 1) frames of f0, after which
// passes grow again at ≤ maxStepPerFrame per frame. With defaults (P_max = 2400 frames,
// 80 s at 30 fps) that bound is reached only when every estimate was wrong; an overload that
// ended cleanly is left as soon as its end is measured (a few frames: the tests measure it).
// UNDER A STEADY LOAD that the larger map does not fit, probes are the only moves, one
// frame each, spaced by P_r frames that double up to P_max: the ladder does not oscillate.
//
// WHY IT CANNOT OSCILLATE UNDER A CONSTANT COST (proof sketch, F̂ = F, integer p):
//  1. s = ((p·n)·256)/n = 256·p exactly for every n, so all samples are equal. The EMA step
//     is d·w rounded toward zero but at least one unit, with w ≤ 1, so |p̂ − s| shrinks by
//     ≥ 1 unit per report and never changes sign: p̂ reaches s exactly in finitely many
//     frames, monotonically. (A step-detect reset or the overrun raise lands on s at once.)
//  2. n* = floor(B·256/p̂) is non-increasing in p̂, so along a monotone p̂ the target moves
//     monotonically, and after step 1 it is constant.
//  3. n moves only toward n* and never past it. Starting from a settled state (cost in the
//     band, or n = n*), a rising p̂ raises the predicted cost of n, so it can leave the band
//     only upward and n only goes down, toward a target that only goes down; symmetrically
//     for a falling p̂. From a cold start p̂ is exact after the first report (step 1), so n*
//     is fixed from then on. Either way n is monotone and bounded, so it becomes constant.
//  4. The ladder goes down on F̂ + min·p̂ > T and up on a predicted cost ≤ T·(1 − h) for
//     the larger map; under a constant cost that prediction equals the cost that made it go
//     down, and the two conditions are disjoint for h ≥ 0, so a rung is never revisited.
// With F̂ < F the samples are s(n) = p + (F − F̂)/n, the map n ↦ floor(B/s(n)) is
// non-decreasing with slope < 1 at its fixed point (which is the true answer (T − F)/p),
// so the iterates are still monotone. With F̂ > F that map is decreasing and successive
// targets alternate; only the dead band damps it. Hence: never overestimate F̂.
//
// Determinism: integers only (no floating point, no libm), so a session driven by
// VirtualClock + CostModel replays to the identical decision sequence.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra::shadow {

class FrameRateController {
 public:
  // num/den, used for weights and fractions so that the arithmetic stays integral.
  struct Ratio {
    uint32_t num;
    uint32_t den;
  };

  // Limits that keep every product in the control law inside int64 (see the .cpp).
  static constexpr int64_t kMaxTargetFrameNs = 10'000'000'000;  // 10 s
  static constexpr uint32_t kMaxPassesLimit = 65'536;
  static constexpr uint32_t kMaxRatioDen = 65'536;

  struct Options {
    int64_t targetFrameNs = 66'666'667;  // 15 fps, the paper's interactive rate (§9, Fig. 7)
    int64_t fixedCostNs = 0;             // F̂ in [0, target); underestimate rather than over
    uint32_t minPasses = 1;
    uint32_t maxPasses = 50;     // the paper's best-quality setting (§9)
    uint32_t initialPasses = 0;  // passes before any report; 0 means minPasses
    uint32_t maxStepPerFrame = 8;
    Ratio hysteresis{1, 10};  // h: dead band [T·(1 − h), T] on the predicted frame cost
    Ratio smoothing{1, 2};    // w: EMA weight of the newest sample, 0 < w ≤ 1
    Ratio stepDetect{1, 4};   // a sample off p̂ by more than this fraction replaces p̂
    // Shadow-map sizes, largest first; the first is the normal size. {256, 128} lets the
    // controller halve the map before it would need fewer than minPasses passes.
    std::vector<uint32_t> shadowMapSizes{256};
    // The larger map's cost estimate expires after this many frames (then doubling after each
    // failed probe, up to maxProbeAfterFrames): the recovery bound above.
    uint32_t probeAfterFrames = 300;
    uint32_t maxProbeAfterFrames = 2400;
  };

  struct Decision {
    uint32_t passes = 0;
    uint32_t shadowMapSize = 0;
    int64_t predictedFrameNs = -1;  // -1 while nothing is known about the cost at this size
    bool fastDrop = false;          // the > 50% overrun path moved n without a step bound
    bool overBudget = false;        // min passes at the smallest map still predicted > target
  };

  // Throws std::invalid_argument, naming the offending field, for inconsistent options.
  explicit FrameRateController(Options options);

  // The passes and shadow-map size for the coming frame. Calling it again before the next
  // report() returns the same decision (the state moves once per measured frame).
  Decision next();

  // The measured time of the frame just rendered with `passes` passes (possibly fewer than
  // decided, when fewer sources were potentially occluded) at the decided map size.
  // `shadowedPixels` is kept for traces; its cost is part of the measured per-pass cost.
  // Throws std::invalid_argument for frameNs < 0 or passes > kMaxPassesLimit.
  void report(int64_t frameNs, uint32_t passes, uint64_t shadowedPixels);

  // The per-pass cost estimate p̂ in ns × 256 (0 before the first report); for traces.
  int64_t perPassEstimateQ8() const { return perPassQ8_; }
  uint64_t lastShadowedPixels() const { return lastShadowedPixels_; }
  const Options& options() const { return options_; }

 private:
  int64_t predictedQ8(uint32_t passes, int64_t perPassQ8) const;
  void measureRatio(int64_t firstSampleQ8);

  Options options_;
  uint32_t passes_;
  size_t rung_ = 0;
  int64_t perPassQ8_ = 0;       // 0: unknown
  bool resetEstimate_ = false;  // the next sample replaces p̂ (the map size changed)
  bool overran_ = false;        // the last frame took > 1.5 × target
  bool decided_ = false;
  Decision decision_;
  uint64_t frames_ = 0;  // reports with passes > 0: the clock of the ratios' ages
  // Per boundary r ≥ 1 (between shadowMapSizes[r − 1] and [r]): ρ_r in Q8 (0: never
  // measured), the frame it was measured at, and the current expiry P_r.
  std::vector<int64_t> ratioQ8_;
  std::vector<uint64_t> ratioFrame_;
  std::vector<uint32_t> probeAfter_;
  // The crossing in flight: the rung just left, its p̂, and whether it was a probe (a climb
  // on an expired ratio); resolved by the first report at the new rung.
  size_t crossedFrom_ = 0;
  int64_t crossedFromQ8_ = 0;
  bool probing_ = false;
  bool probeArrived_ = false;  // the last crossing was a probe and has been measured
  uint64_t lastShadowedPixels_ = 0;
};

}  // namespace penumbra::shadow
