#include "reference/differential.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace penumbra::reference {

double inverseTone(const shadow::ToneCurve& tone, uint8_t code) {
  // Walk down to the nearest code T produces (code 0 always is: radiance 0 maps to it
  // unless threshold(1) <= 0, handled below).
  for (int k = code; k >= 1; --k) {
    const double lo = tone.threshold(k);
    if (!std::isfinite(lo)) continue;
    if (k == 255) return lo;
    const double hi = tone.threshold(k + 1);
    if (!(hi > lo)) continue;  // empty interval: T never outputs k
    if (!std::isfinite(hi)) return lo;
    const double mid = lo + 0.5 * (hi - lo);
    // In floating point the midpoint of two neighbouring doubles can round up to `hi`.
    return mid < hi && mid >= lo ? mid : lo;
  }
  const double t1 = tone.threshold(1);
  if (t1 > 0) return 0.5 * t1;
  // Code 0 only for negative radiance: any value below threshold(1).
  return std::nextafter(t1, -INFINITY);
}

ToneInterval toneInterval(const shadow::ToneCurve& tone, uint8_t code) {
  const double lo = code == 0 ? 0.0 : tone.threshold(code);
  const double next = code == 255 ? INFINITY : tone.threshold(code + 1);
  // T produces `code` exactly when its interval is non-empty (a curve whose threshold(1) is
  // not positive gives code 0 to negative radiance only: no interval among radiances >= 0).
  // The interval is half-open: its largest member is the double below the next threshold.
  if (std::isfinite(lo) && next > lo) return {lo, std::nextafter(next, -INFINITY)};
  const double point = inverseTone(tone, code);
  return {point, point};
}

std::vector<double> inverseToneTable(const shadow::ToneCurve& tone) {
  std::vector<double> table(256);
  for (int k = 0; k < 256; ++k) table[size_t(k)] = inverseTone(tone, static_cast<uint8_t>(k));
  return table;
}

DifferentialFrame composeDifferential(const ReferenceImage& image,
                                      std::span<const uint8_t> background,
                                      const shadow::ToneCurve& tone) {
  const size_t pixels = size_t{image.width} * image.height;
  if (background.size() != pixels * 4) {
    throw std::invalid_argument("composeDifferential: the background is " +
                                std::to_string(background.size()) + " bytes, the image needs " +
                                std::to_string(pixels * 4));
  }
  if (image.roomDelta.size() != pixels || image.objectRadiance.size() != pixels ||
      image.objectCoverage.size() != pixels) {
    throw std::invalid_argument("composeDifferential: reference image buffers have the wrong size");
  }
  const std::vector<double> inverse = inverseToneTable(tone);
  std::vector<ToneInterval> interval(256);
  for (int k = 0; k < 256; ++k) interval[size_t(k)] = toneInterval(tone, static_cast<uint8_t>(k));
  DifferentialFrame out;
  out.width = image.width;
  out.height = image.height;
  out.rgba.resize(pixels * 4);
  out.lower.resize(pixels * 4);
  out.upper.resize(pixels * 4);
  out.radiance.resize(pixels);
  out.shadowMask.assign(pixels, 0);
  for (size_t i = 0; i < pixels; ++i) {
    const double c = image.objectCoverage[i];
    bool changed = false;
    for (int ch = 0; ch < 3; ++ch) {
      const uint8_t b = background[4 * i + size_t(ch)];
      const double delta = double(image.roomDelta[i][ch]);
      const double object = double(image.objectRadiance[i][ch]);
      // c == 0 must leave the room's radiance untouched, and a fully covered pixel must not
      // see it at all (0 * inf is NaN for the upper end of code 255).
      const auto mix = [&](double lb) {
        const double room = lb - delta;
        return c >= 1 ? object : c > 0 ? (1.0 - c) * room + c * object : room;
      };
      const double hdr = mix(inverse[b]);
      out.radiance[i][ch] = static_cast<float>(hdr);
      const uint8_t v = tone(hdr);
      out.rgba[4 * i + size_t(ch)] = v;
      out.lower[4 * i + size_t(ch)] = tone(mix(interval[b].lo));
      out.upper[4 * i + size_t(ch)] = tone(mix(interval[b].hi));
      changed = changed || v != b;
    }
    out.rgba[4 * i + 3] = out.lower[4 * i + 3] = out.upper[4 * i + 3] = 255;
    if (c > 0) {
      ++out.objectPixels;
    } else if (changed) {
      out.shadowMask[i] = 255;
      ++out.shadowPixels;
    }
  }
  return out;
}

size_t changedPixels(const DifferentialFrame& frame, std::span<const uint8_t> background) {
  if (background.size() != frame.rgba.size()) {
    throw std::invalid_argument("changedPixels: background size differs from the frame's");
  }
  size_t changed = 0;
  for (size_t i = 0; i < frame.rgba.size(); i += 4) {
    changed += std::memcmp(&frame.rgba[i], &background[i], 3) != 0;
  }
  return changed;
}

double shadowNoiseRms(const DifferentialFrame& a, const DifferentialFrame& b, size_t* samples) {
  if (a.rgba.size() != b.rgba.size() || a.shadowMask.size() != b.shadowMask.size()) {
    throw std::invalid_argument("shadowNoiseRms: the two renders differ in size");
  }
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < a.shadowMask.size(); ++i) {
    if (!a.shadowMask[i] && !b.shadowMask[i]) continue;
    for (size_t c = 0; c < 3; ++c) {
      const double d = double(a.rgba[4 * i + c]) - b.rgba[4 * i + c];
      sum += d * d;
      ++count;
    }
  }
  if (samples) *samples = count;
  return count ? std::sqrt(sum / double(count) / 2.0) : 0.0;
}

std::vector<uint8_t> shadowMaskRgba(const DifferentialFrame& frame) {
  std::vector<uint8_t> rgba(frame.shadowMask.size() * 4);
  for (size_t i = 0; i < frame.shadowMask.size(); ++i) {
    for (size_t c = 0; c < 3; ++c) rgba[4 * i + c] = frame.shadowMask[i];
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

}  // namespace penumbra::reference
