// The camera response T() of Gibson 2003 §3 ("calibrated camera response function") and
// the lookups the per-frame path reads it through: ToneCurve (radiance -> 8-bit code, one
// binary search over the 255 code thresholds; the reference every fast path must equal),
// ToneLut (the same codes for float radiance without the search) and ToneInverse (T^-1 at
// each code, for environment maps rendered in 8 bits). lighting/camera_response.h recovers
// the curve from photographs; the scene bundle stores its thresholds.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/colour.h"

namespace penumbra::shadow {

// A monotone camera response: radiance -> 8-bit code (Gibson 2003 §3, "calibrated camera
// response function T()"). Stored as the 255 radiances at which the code steps up, so a
// lookup is one binary search over a sorted table: no libm in the per-vertex path, and
// monotonicity is exact (the telescoping property depends on it).
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

  // T(L) for one channel. NaN maps to 0.
  uint8_t operator()(double radiance) const;
  core::Rgb8 map(const glm::dvec3& radiance) const;

  // The smallest radiance with code >= k, k in 1..255 (+inf if never reached).
  double threshold(int code) const { return thresholds_[code - 1]; }

 private:
  std::array<double, 255> thresholds_{};
};

// T() for float radiance, the same codes as ToneCurve::operator() but without its binary
// search per channel: a table indexed by the top 15 bits of the (non-negative) float gives
// the code at the bucket's lower end, and a short forward scan over the thresholds
// finishes (a bucket spans 1/128 of an octave, so the scan is rarely more than one step).
// Exact for every input; NaN → 0; negative values take ToneCurve's own path. 32 KiB.
class ToneLut {
 public:
  explicit ToneLut(const ToneCurve& curve);
  uint8_t operator()(float radiance) const;
  core::Rgb8 map(const glm::vec3& radiance) const {
    return {(*this)(radiance.x), (*this)(radiance.y), (*this)(radiance.z)};
  }

 private:
  ToneCurve curve_;
  std::array<double, 255> thresholds_;
  std::vector<uint8_t> start_;  // per bucket: the code of its lowest float
};

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
