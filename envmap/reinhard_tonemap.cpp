#include "envmap/reinhard_tonemap.h"

#include <algorithm>
#include <cmath>

#include "core/colour.h"
#include "envmap/portable_log_exp.h"

namespace penumbra::envmap {

namespace {

// The sRGB encoding is a table over linear [0, 1] in this many steps: at 1/16384 the darkest
// step (slope 12.92) is 0.2 code values, so the table is exact up to rounding ties.
constexpr uint32_t kSrgbSteps = 16384;
constexpr double kLn2 = 0.69314718055994530942;

// IEC 61966-2-1: 12.92 v below 0.0031308, else 1.055 v^(1/2.4) − 0.055; × 255, rounded.
uint8_t srgbCode(double v) {
  const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * portableExp(portableLog(v) / 2.4) - 0.055;
  return uint8_t(std::clamp(std::floor(e * 255.0 + 0.5), 0.0, 255.0));
}

double smooth(double previous, double current, double s) {
  return previous + s * (current - previous);
}

}  // namespace

ReinhardToneMapper::ReinhardToneMapper(const ReinhardOptions& options) : options_(options) {
  if (!(options.key >= 0) || !(options.smoothing > 0 && options.smoothing <= 1) ||
      !(options.delta > 0))
    throw ToneMapError("tone mapping", "",
                       "needs key >= 0, smoothing in (0, 1] and delta > 0 (got key " +
                           std::to_string(options.key) + ", smoothing " +
                           std::to_string(options.smoothing) + ", delta " +
                           std::to_string(options.delta) + ")");
  srgb_.resize(kSrgbSteps + 1);
  for (uint32_t i = 0; i <= kSrgbSteps; ++i) srgb_[i] = srgbCode(double(i) / kSrgbSteps);
}

double ReinhardToneMapper::worldLuminance() const {
  return portableExp(logWorld_);
}
double ReinhardToneMapper::key() const {
  return portableExp(logKey_);
}
double ReinhardToneMapper::white() const {
  return portableExp(logWhite_);
}

core::Image8 ReinhardToneMapper::map(const core::ImageF& hdr, const std::string& label) {
  if (hdr.width == 0 || hdr.height == 0 || !hdr.hasExpectedSize())
    throw ToneMapError(label, "",
                       "needs a non-empty RGB image (" + std::to_string(hdr.width) + " × " +
                           std::to_string(hdr.height) + ", " + std::to_string(hdr.pixels.size()) +
                           " samples)");
  const size_t n = hdr.pixelCount();
  std::vector<double> luminance(n);
  double logSum = 0, logMin = 0, logMax = 0, maxLuminance = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* p = &hdr.pixels[i * 3];
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(p[c]) || p[c] < 0)
        throw ToneMapError(
            label,
            "pixel (" + std::to_string(i % hdr.width) + ", " + std::to_string(i / hdr.width) + ")",
            "radiance " + std::to_string(p[c]) + " is not a finite non-negative number");
    luminance[i] = core::luminance(glm::dvec3(p[0], p[1], p[2]));
    const double l = portableLog(options_.delta + luminance[i]);  // Reinhard 2002, eq. 1
    logSum += l;
    logMin = i == 0 ? l : std::min(logMin, l);
    logMax = i == 0 ? l : std::max(logMax, l);
    maxLuminance = std::max(maxLuminance, luminance[i]);
  }
  const double logWorld = logSum / double(n);
  // Reinhard 2002b: the key from where the log-average sits in the log range (in stops).
  double logKey = portableLog(options_.key > 0 ? options_.key : 0.18);
  if (options_.key == 0 && logMax > logMin)
    logKey += 2 * kLn2 * (2 * logWorld - logMin - logMax) / (logMax - logMin);
  // Lwhite: the largest luminance scaled by a / L̄w (eq. 2), at least the scaled δ.
  const double logWhite = logKey - logWorld + portableLog(std::max(maxLuminance, options_.delta));
  if (!started_) {
    logWorld_ = logWorld, logKey_ = logKey, logWhite_ = logWhite;
    started_ = true;
  } else {
    logWorld_ = smooth(logWorld_, logWorld, options_.smoothing);
    logKey_ = smooth(logKey_, logKey, options_.smoothing);
    logWhite_ = smooth(logWhite_, logWhite, options_.smoothing);
  }
  const double scale = portableExp(logKey_ - logWorld_);
  const double white = portableExp(logWhite_);
  const double inverseWhite2 = 1.0 / (white * white);

  core::Image8 out(hdr.width, hdr.height, 3, label);
  for (size_t i = 0; i < n; ++i) {
    if (!(luminance[i] > 0)) continue;  // black stays black
    const double l = scale * luminance[i];
    const double ld = l * (1.0 + l * inverseWhite2) / (1.0 + l);  // eq. 4
    const double ratio = ld / luminance[i];
    for (int c = 0; c < 3; ++c) {
      const double v = std::min(1.0, ratio * hdr.pixels[i * 3 + c]);
      // v >= 0: adding 0.5 and truncating is round-half-up, exactly, without libm.
      // NOLINTNEXTLINE(bugprone-incorrect-roundings)
      out.pixels[i * 3 + c] = srgb_[uint32_t(v * kSrgbSteps + 0.5)];
    }
  }
  return out;
}

}  // namespace penumbra::envmap
