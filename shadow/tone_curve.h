// The camera response T() of Gibson 2003 §3 ("calibrated camera response function") and
// the lookups the per-frame path reads it through: ToneCurve (radiance -> 8-bit code; a
// bucket table and a short scan, equal to a binary search over the 255 code thresholds,
// which stays as the reference) and ToneInverse (T^-1 at each code, for environment maps
// rendered in 8 bits). lighting/camera_response.h recovers the curve from photographs; the
// scene bundle stores its thresholds.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/colour.h"

namespace penumbra::shadow {

// A monotone camera response: radiance -> 8-bit code (Gibson 2003 §3, "calibrated camera
// response function T()"). Defined by the 255 radiances at which the code steps up: T(L) is
// the number of thresholds <= L, so monotonicity is exact (the telescoping of Fig. 4 depends
// on it) and no libm runs in the per-vertex path.
//
// T runs per receiver vertex and per source several times a frame (a binary search per
// channel was 17.9 % of the kiosk frame in issue 13's profile), so operator() does not search: a
// table indexed by the top 15 bits of a float gives the code at the bucket's lowest float, and a
// forward scan over the thresholds finishes. Exact, by monotonicity: for L >= 0 let f be the
// largest float
// <= L and f0 the lowest float of f's bucket; f0 <= L, so the table's T(f0) counts only
// thresholds <= L, and the scan, comparing L itself, stops at T(L). A bucket spans 1/128 of
// an octave, so the scan is rarely more than one step. Negative radiance (never produced by
// the pipeline) takes the search. The table (32 KiB) is built once per curve and shared by
// its copies.
class ToneCurve {
 public:
  struct Sample {
    double radiance;  // non-decreasing over the samples
    double value;     // continuous output in [0, 255], non-decreasing
  };

  // Piecewise-linear response through `samples` (at least two), constant outside them;
  // a radiance maps to the code nearest its interpolated value (ties upwards).
  // Throws std::invalid_argument for fewer than two or non-monotone samples.
  static ToneCurve fromSamples(std::span<const Sample> samples);

  // An sRGB-like display response: value = 255 * min(1, exposure * L)^(1 / gamma),
  // sampled at every half code.
  static ToneCurve gamma(double exposure, double gamma = 2.2);

  // The curve with these code thresholds (as returned by threshold(1..255)), e.g. read
  // back from a scene bundle. Throws std::invalid_argument unless non-decreasing.
  static ToneCurve fromThresholds(const std::array<double, 255>& thresholds);
  std::array<double, 255> thresholds() const { return thresholds_; }

  // T(L) for one channel (float radiance converts exactly). NaN maps to 0.
  uint8_t operator()(double radiance) const;
  template <typename T>
  core::Rgb8 map(const glm::vec<3, T>& radiance) const {
    return {(*this)(radiance.x), (*this)(radiance.y), (*this)(radiance.z)};
  }

  // The definition: the number of thresholds <= radiance, by binary search (NaN -> 0).
  // operator() equals it for every input (tests/tone_curve_test.cpp).
  uint8_t bySearch(double radiance) const;

  // The smallest radiance with code >= k, k in 1..255 (+inf if never reached).
  double threshold(int code) const { return thresholds_[code - 1]; }

  // T(L) in continuous levels, for intensity transfers finer than a code
  // (docs/pipeline-spec.md §5): piecewise linear through (threshold(k), k - 0.5) — the points
  // where rounding the curve's own interpolated value steps from k - 1 to k — from (0, 0)
  // and flat at 255 from threshold(255) on, so it stays within half a level of operator()
  // (rounding it gives the code, ties aside). Non-decreasing, as the telescoping of Fig. 4
  // needs. Exactly: with k = operator()(L), value = base_k + (L - threshold(k)) * slope_k
  // in binary64 (no FMA), slope_k = 1 / (threshold(k + 1) - threshold(k)) rounded once;
  // code 0 runs from radiance 0 at slope 0.5 / threshold(1) and clamps at 0; a code whose
  // interval has an infinite end is flat at k. NaN maps to 0.
  double levels(double radiance) const;
  template <typename T>
  glm::dvec3 levels(const glm::vec<3, T>& radiance) const {
    return {levels(radiance.x), levels(radiance.y), levels(radiance.z)};
  }

 private:
  static constexpr size_t kBuckets = size_t{1} << 15;  // sign-free float bits >> 16
  void buildBuckets();

  using Buckets = std::array<uint8_t, kBuckets>;
  // A default-constructed curve's (all thresholds 0: every radiance >= 0 is code 255),
  // shared, so that operator() never meets a curve without a table.
  static std::shared_ptr<const Buckets> saturatedBuckets();

  std::array<double, 255> thresholds_{};
  // Per bucket: bySearch of its lowest float.
  std::shared_ptr<const Buckets> buckets_ = saturatedBuckets();
  // Per code k: levels() = base[k] + (L - from[k]) * slope[k] (built with the buckets).
  struct Segments {
    std::array<double, 256> base{}, from{}, slope{};
  };
  std::shared_ptr<const Segments> segments_;
};

// Linear accumulation's shade table (raster::FrameContent::shadeTable, spec §8): entry
// c * 511 + q is T(T^-1(c) (1 - q / 510)), the code of a pixel of code c once the share
// q / 510 of its light is occluded, with T^-1 = ToneInverse (the middle of c's radiance
// interval, so q = 0 gives c back). Multiplying the radiance rather than subtracting codes is
// what makes the shadow exact wherever the shares are: T's curvature never enters the sums.
std::vector<uint8_t> linearShadeTable(const ToneCurve& tone);

// T^-1 at the middle of each code's radiance interval (code 0 → 0; code 255 → its
// threshold, the least radiance that saturates).
class ToneInverse {
 public:
  explicit ToneInverse(const ToneCurve& curve);
  float operator()(uint8_t code) const { return table_[code]; }

 private:
  std::array<float, 256> table_{};
};

}  // namespace penumbra::shadow
