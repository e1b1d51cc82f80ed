// Shared by the HDR tests: brackets made by pushing a known radiance image through a known
// camera response, so recovery and merge can be checked against the truth.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "lighting/hdr_image.h"

namespace penumbra::lighting::testutil {

// The "true" camera: code = round(255 * min(1, gain_c * X)^(1 / gamma_c)), X = E * dt, a
// different gain and gamma per channel.
inline constexpr double kGain[3] = {1.0, 0.8, 1.25};
inline constexpr double kGamma[3] = {2.2, 1.8, 2.6};

inline uint8_t trueCode(int c, double x) {
  const double v = 255.0 * std::pow(std::min(1.0, kGain[c] * x), 1.0 / kGamma[c]);
  return uint8_t(std::lround(v));
}

// ln X recorded at the middle of code z's range: the truth g(z) (up to a constant).
inline double trueLogExposure(int c, int z) {
  return kGamma[c] * std::log(z / 255.0) - std::log(kGain[c]);
}

// The exposure times of the tests' brackets: five stops two apart.
inline constexpr double kBracketTimes[5] = {1.0 / 16, 1.0 / 4, 1.0, 4.0, 16.0};

inline std::vector<Exposure> makeBracket(const core::ImageF& radiance,
                                         std::span<const double> times) {
  std::vector<Exposure> out;
  for (double t : times) {
    Exposure e;
    e.name = "dt=" + std::to_string(t);
    e.seconds = t;
    e.image.width = radiance.width;
    e.image.height = radiance.height;
    e.image.pixels.resize(radiance.pixels.size());
    for (size_t i = 0; i < radiance.pixels.size(); ++i) {
      e.image.pixels[i] = trueCode(int(i % 3), double(radiance.pixels[i]) * t);
    }
    out.push_back(std::move(e));
  }
  return out;
}

// A smooth radiance field spanning about e^-6 .. e^2 (a 3,000:1 range; no code
// clipped in every exposure of the bracket 1/16 .. 16), different per channel.
inline core::ImageF gradientField(int w, int h) {
  core::ImageF img;
  img.width = w;
  img.height = h;
  img.pixels.resize(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double s = double(x) / (w - 1), t = double(y) / (h - 1);
        const double l = -6.0 + 8.0 * s + 0.3 * std::sin(6.0 * t + c) - 0.2 * c * t;
        img.pixels[(size_t(y) * w + x) * 3 + c] = float(std::exp(l));
      }
    }
  }
  return img;
}

// Sorted relative errors |merged / (k_c * truth) - 1| over the channel values with
// use[i] != 0 (all when `use` is empty). k_c, the median ratio of channel c, removes the
// free per-channel constant of the response (camera_response.h).
inline std::vector<double> relativeErrors(const core::ImageF& merged, const core::ImageF& truth,
                                          const std::vector<uint8_t>& use = {}) {
  std::vector<double> err;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> ratio;
    for (size_t i = size_t(c); i < truth.pixels.size(); i += 3) {
      if (use.empty() || use[i])
        ratio.push_back(double(merged.pixels[i]) / double(truth.pixels[i]));
    }
    if (ratio.empty()) continue;
    std::vector<double> sorted = ratio;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double k = sorted[sorted.size() / 2];
    for (double r : ratio) err.push_back(std::abs(r / k - 1.0));
  }
  std::sort(err.begin(), err.end());
  return err;
}

inline double quantile(const std::vector<double>& sorted, double q) {
  return sorted[size_t(q * double(sorted.size() - 1))];
}

}  // namespace penumbra::lighting::testutil
