#include "envmap/probe_sequences.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/colour.h"
#include "core/random.h"

namespace penumbra::envmap {

namespace {

// The direction of lat-long pixel (x, y)'s centre (lat_long.h's convention).
glm::dvec3 latLongDirection(const core::ImageF& image, uint32_t x, uint32_t y) {
  const double theta = std::numbers::pi * (y + 0.5) / image.height;
  const double phi = 2 * std::numbers::pi * (x + 0.5) / image.width;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

double pixelLuminance(const core::ImageF& image, uint32_t x, uint32_t y) {
  const float* p = image.pixel(x, y);
  return core::luminance(glm::dvec3(p[0], p[1], p[2]));
}

}  // namespace

glm::dvec3 brightestDirection(const core::ImageF& latLong) {
  if (latLong.width == 0 || latLong.height < 2 || !latLong.hasExpectedSize())
    throw std::invalid_argument("light probe: empty or holding the wrong number of samples");
  double best = -1;
  uint32_t bx = 0, by = 0;
  for (uint32_t y = 0; y < latLong.height / 2; ++y)
    for (uint32_t x = 0; x < latLong.width; ++x)
      if (const double l = pixelLuminance(latLong, x, y); l > best) best = l, bx = x, by = y;
  return latLongDirection(latLong, bx, by);
}

core::ImageF animateProbe(const core::ImageF& probe, const ProbeAnimation& a, uint64_t frame) {
  const glm::dvec3 bright = brightestDirection(probe);
  double brightLuminance = 0;
  for (uint32_t y = 0; y < probe.height / 2; ++y)
    for (uint32_t x = 0; x < probe.width; ++x)
      brightLuminance = std::max(brightLuminance, pixelLuminance(probe, x, y));
  const double cosLamp = std::cos(a.lampRadiusDegrees * std::numbers::pi / 180);
  const bool lampOff = a.lampOffFrame >= 0 && int64_t(frame) >= a.lampOffFrame;
  double cloud = 0;  // s(t)
  if (a.cloudTo > a.cloudFrom && int64_t(frame) >= a.cloudFrom && int64_t(frame) <= a.cloudTo) {
    const double t = double(int64_t(frame) - a.cloudFrom) / double(a.cloudTo - a.cloudFrom);
    cloud = 1 - std::fabs(2 * t - 1);
  }
  const double cloudRadius = a.cloudRadiusDegrees * std::numbers::pi / 180;
  const double gain =
      1 + a.flickerDepth * std::sin(2 * std::numbers::pi * a.flickerHz * double(frame) / a.frameHz);
  // The rotation moves the picture, not the lamp's and the cloud's place in it: they are
  // looked up in the probe's own frame, at the direction turned back.
  const double turn = a.degreesPerFrame * double(frame) / 360.0;
  const uint64_t key = core::splitmix64(a.seed) ^ frame;

  core::ImageF out(probe.width, probe.height);
  for (uint32_t y = 0; y < probe.height; ++y)
    for (uint32_t x = 0; x < probe.width; ++x) {
      double sx = x - turn * probe.width;
      sx -= std::floor(sx / probe.width) * probe.width;
      const uint32_t src = std::min(probe.width - 1, uint32_t(sx));
      const glm::dvec3 d = latLongDirection(probe, src, y);
      double factor = gain;
      const double cosAngle = glm::dot(d, bright);
      if (lampOff && cosAngle >= cosLamp && pixelLuminance(probe, src, y) > 0.2 * brightLuminance)
        factor *= a.lampOffLevel;
      if (cloud > 0) {
        const double angle = std::acos(std::clamp(cosAngle, -1.0, 1.0)) / cloudRadius;
        const double w = angle >= 1 ? 0 : (1 - angle * angle) * (1 - angle * angle);
        factor *= 1 - a.cloudDepth * cloud * w;
      }
      const float* p = probe.pixel(src, y);
      float* q = out.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        double v = std::max(0.0f, p[c]) * factor;
        if (a.noise > 0) {
          const uint64_t sample = (uint64_t(y) * probe.width + x) * 3 + uint64_t(c);
          v *= 1 + a.noise * (2 * core::unitSample(key, sample) - 1);
        }
        q[c] = float(v);
      }
    }
  return out;
}

}  // namespace penumbra::envmap
