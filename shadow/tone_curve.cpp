#include "shadow/tone_curve.h"

#include "raster/frame_trace.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::shadow {

ToneCurve ToneCurve::fromThresholds(const std::array<double, 255>& thresholds) {
  for (size_t k = 1; k < thresholds.size(); ++k) {
    if (!(thresholds[k] >= thresholds[k - 1])) {
      throw std::invalid_argument("tone curve: thresholds must be non-decreasing (code " +
                                  std::to_string(k + 1) + ")");
    }
  }
  ToneCurve curve;
  curve.thresholds_ = thresholds;
  curve.buildBuckets();
  return curve;
}

ToneCurve ToneCurve::fromSamples(std::span<const Sample> samples) {
  if (samples.size() < 2) throw std::invalid_argument("ToneCurve: need at least two samples");
  for (size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    if (!std::isfinite(s.radiance) || !std::isfinite(s.value)) {
      throw std::invalid_argument("ToneCurve: samples must be finite");
    }
    if (i > 0 && (s.radiance < samples[i - 1].radiance || s.value < samples[i - 1].value)) {
      throw std::invalid_argument("ToneCurve: samples must be non-decreasing");
    }
  }
  ToneCurve curve;
  const double inf = std::numeric_limits<double>::infinity();
  size_t seg = 0;
  for (int k = 1; k <= 255; ++k) {
    // Code k starts where the interpolated value reaches k - 0.5 (round to nearest).
    const double level = k - 0.5;
    if (samples.front().value >= level) {
      curve.thresholds_[k - 1] = -inf;  // every radiance already reaches code k
      continue;
    }
    while (seg + 1 < samples.size() && samples[seg + 1].value < level) ++seg;
    if (seg + 1 == samples.size()) {
      curve.thresholds_[k - 1] = inf;
      continue;
    }
    const Sample& a = samples[seg];
    const Sample& b = samples[seg + 1];
    // a.value < level <= b.value, so b.value > a.value and the division is safe.
    const double f = (level - a.value) / (b.value - a.value);
    curve.thresholds_[k - 1] = a.radiance + f * (b.radiance - a.radiance);
  }
  // Interpolation keeps the table sorted; enforce it against rounding so that the
  // binary search (and hence T's monotonicity) is exact.
  for (int k = 1; k < 255; ++k) {
    curve.thresholds_[k] = std::max(curve.thresholds_[k], curve.thresholds_[k - 1]);
  }
  curve.buildBuckets();
  return curve;
}

ToneCurve ToneCurve::gamma(double exposure, double gamma) {
  if (!(exposure > 0) || !(gamma > 0)) {
    throw std::invalid_argument("ToneCurve::gamma: exposure and gamma must be positive");
  }
  std::vector<Sample> samples;
  samples.reserve(511);
  for (int h = 0; h <= 510; ++h) {
    const double value = 0.5 * h;
    samples.push_back({std::pow(value / 255.0, gamma) / exposure, value});
  }
  return fromSamples(samples);
}

uint8_t ToneCurve::bySearch(double radiance) const {
  if (std::isnan(radiance)) return 0;
  const auto it = std::upper_bound(thresholds_.begin(), thresholds_.end(), radiance);
  return static_cast<uint8_t>(it - thresholds_.begin());
}

std::shared_ptr<const ToneCurve::Buckets> ToneCurve::saturatedBuckets() {
  static const std::shared_ptr<const Buckets> table = [] {
    auto t = std::make_shared<Buckets>();
    t->fill(255);
    return t;
  }();
  return table;
}

void ToneCurve::buildBuckets() {
  auto table = std::make_shared<Buckets>();
  for (uint32_t b = 0; b < kBuckets; ++b) {
    (*table)[b] = bySearch(double(std::bit_cast<float>(b << 16)));  // NaN buckets: never read
  }
  buckets_ = std::move(table);
  // The segments of levels(): code k covers [threshold(k), threshold(k + 1)) and runs from
  // k - 0.5 to k + 0.5 over it.
  auto segments = std::make_shared<Segments>();
  for (int k = 0; k < 256; ++k) {
    const double from = k == 0 ? 0.0 : thresholds_[size_t(k - 1)];
    const double to = k == 255 ? std::numeric_limits<double>::infinity() : thresholds_[size_t(k)];
    const double span = k == 0 ? 0.5 : 1.0;
    const double width = to - from;
    if (std::isfinite(from) && std::isfinite(to) && width > 0) {
      segments->base[size_t(k)] = k == 0 ? 0.0 : k - 0.5;
      segments->from[size_t(k)] = from;
      segments->slope[size_t(k)] = span / width;
    } else {
      segments->base[size_t(k)] = k;  // flat: never left, or never reached
    }
  }
  segments_ = std::move(segments);
}

double ToneCurve::levels(double radiance) const {
  if (std::isnan(radiance)) return 0.0;
  if (segments_ == nullptr) return 255.0;  // a default curve: every radiance saturates
  const size_t k = (*this)(radiance);
  const Segments& s = *segments_;
  // Code 0 below radiance 0 would go negative.
  return std::max(0.0, s.base[k] + (radiance - s.from[k]) * s.slope[k]);
}

uint8_t ToneCurve::operator()(double radiance) const {
  // The bucket straight from the double's bits where the largest float <= radiance is a
  // normal float: its exponent field is the double's rebiased (1023 -> 127) and its top 7
  // mantissa bits are the double's top 7, as truncating the mantissa to float's 23 bits
  // rounds down and keeps them. So (bits >> 45) - (1023 - 127) * 128 is that float's
  // (bits >> 16), for exponent fields 1..254. Radiance in [2^-126, 2^128): every lit
  // receiver; -0, tiny, huge and NaN values take the general path below.
  constexpr int64_t kRebias = int64_t{1023 - 127} << 7;
  const int64_t fromDouble = int64_t(std::bit_cast<uint64_t>(radiance) >> 45) - kRebias;
  if (fromDouble >= (int64_t{1} << 7) && fromDouble < (int64_t{255} << 7)) {
    unsigned code = (*buckets_)[static_cast<size_t>(fromDouble)];
    while (code < 255 && thresholds_[code] <= radiance) ++code;
    return static_cast<uint8_t>(code);
  }
  // NaN and negative radiance take the definition.
  if (!(radiance >= 0.0)) return bySearch(radiance);
  // f: the largest float <= radiance (FLT_MAX above it). The mask maps -0 to +0's bucket.
  constexpr double kMaxFloat = std::numeric_limits<float>::max();
  float f =
      radiance >= kMaxFloat ? std::numeric_limits<float>::max() : static_cast<float>(radiance);
  if (double(f) > radiance) f = std::nextafter(f, 0.0f);
  unsigned code = (*buckets_)[(std::bit_cast<uint32_t>(f) >> 16) & (kBuckets - 1)];
  while (code < 255 && thresholds_[code] <= radiance) ++code;
  return static_cast<uint8_t>(code);
}

ToneInverse::ToneInverse(const ToneCurve& curve) {
  table_[0] = 0.0f;
  for (int c = 1; c < 255; ++c) {
    table_[size_t(c)] = static_cast<float>(0.5 * (curve.threshold(c) + curve.threshold(c + 1)));
  }
  // The least float that still saturates (a plain rounding may land just below).
  const double top = curve.threshold(255);
  float f = static_cast<float>(top);
  if (double(f) < top) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  table_[255] = f;
  for (float& v : table_) {
    if (!std::isfinite(v)) v = 0.0f;  // a code the curve never reaches
  }
}

std::vector<uint8_t> linearShadeTable(const ToneCurve& tone) {
  const ToneInverse inverse(tone);
  constexpr size_t kSteps = raster::kShadeSteps;
  std::vector<uint8_t> table(raster::kShadeCodes * kSteps);
  for (size_t c = 0; c < raster::kShadeCodes; ++c) {
    const double radiance = inverse(static_cast<uint8_t>(c));
    // q = 0 is the unshadowed pixel itself, also for a code whose interval is empty (where
    // T^-1 has no middle and T(T^-1(c)) may be another code).
    table[c * kSteps] = static_cast<uint8_t>(c);
    for (size_t q = 1; q < kSteps; ++q) {
      const uint8_t code = tone(radiance * (1.0 - double(q) / double(kSteps - 1)));
      table[c * kSteps + q] = std::min(code, table[c * kSteps + q - 1]);  // never brighter
    }
  }
  return table;
}

}  // namespace penumbra::shadow
