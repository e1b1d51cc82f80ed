#include "platform/environment_response.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "envmap/portable_log_exp.h"

namespace penumbra::platform {
namespace {

// x^p for x in (0, 1] by exp(p·ln x): the portable functions, not libm's pow.
double power(double x, double p) {
  return envmap::portableExp(p * envmap::portableLog(x));
}

}  // namespace

ChannelResponse curveResponse(double gamma) {
  if (!(gamma >= 0) || !std::isfinite(gamma))
    throw std::invalid_argument("environment response: gamma must be 0 (sRGB) or positive");
  std::array<double, 256> curve{};  // curve[0] = 0
  for (int v = 1; v < 256; ++v) {
    const double c = v / 255.0;
    if (gamma == 0)
      curve[size_t(v)] = c <= 0.04045 ? c / 12.92 : power((c + 0.055) / 1.055, 2.4);
    else
      curve[size_t(v)] = power(c, gamma);
  }
  return {curve, curve, curve};
}

ChannelResponse calibratedResponse(const kiosk::CameraResponseCurves& curves) {
  ChannelResponse out{};
  for (size_t c = 0; c < 3; ++c)
    for (size_t z = 0; z < 256; ++z) out[c][z] = envmap::portableExp(curves.logExposure[c][z]);
  return out;
}

ChannelTables radianceTables(const ChannelResponse& response, double exposureMs,
                             double exposureScale) {
  if (!(exposureMs > 0) || !std::isfinite(exposureMs))
    throw std::invalid_argument("environment response: the exposure time must be positive");
  if (!(exposureScale > 0) || !std::isfinite(exposureScale))
    throw std::invalid_argument("environment response: exposure_scale must be positive");
  ChannelTables tables{};
  for (size_t c = 0; c < 3; ++c)
    for (size_t z = 0; z < 256; ++z)
      tables[c][z] = float(response[c][z] / exposureMs / exposureScale);
  return tables;
}

std::array<float, 256> inverseResponse(double gamma, double exposureScale) {
  return radianceTables(curveResponse(gamma), 1, exposureScale)[0];
}

uint8_t encodeSrgb8(double linear) {
  const double l = std::clamp(linear, 0.0, 1.0);
  const double c = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
  return static_cast<uint8_t>(std::lround(c * 255));
}

size_t linearise(const uint8_t* bgr, size_t stride, uint32_t width, uint32_t height,
                 const ChannelTables& tables, core::ImageF& out) {
  if (out.width != width || out.height != height) out = core::ImageF(width, height);
  size_t saturated = 0;
  float* o = out.pixels.data();
  for (uint32_t y = 0; y < height; ++y) {
    const uint8_t* p = bgr + stride * y;
    for (uint32_t x = 0; x < width; ++x, p += 3, o += 3) {
      o[0] = tables[0][p[2]];
      o[1] = tables[1][p[1]];
      o[2] = tables[2][p[0]];
      // Branch-free: one comparison per channel, summed.
      saturated +=
          size_t((p[0] >= kSaturatedValue) | (p[1] >= kSaturatedValue) | (p[2] >= kSaturatedValue));
    }
  }
  return saturated;
}

}  // namespace penumbra::platform
