#include "envmap/lat_long.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace penumbra::envmap {

namespace {
void checkLatLong(const core::ImageF& latLong) {
  if (latLong.width == 0 || latLong.height == 0 || !latLong.hasExpectedSize())
    throw std::invalid_argument("lat-long map: empty or holding the wrong number of samples");
}
}  // namespace

glm::dvec3 sampleLatLong(const core::ImageF& latLong, const glm::dvec3& d) {
  const double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
  double phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * std::numbers::pi;
  const double x = phi / (2 * std::numbers::pi) * latLong.width - 0.5;
  const double y =
      std::clamp(theta / std::numbers::pi * latLong.height - 0.5, 0.0, double(latLong.height - 1));
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const auto w = int64_t(latLong.width);
  const auto col = [&](double c) { return uint32_t(((int64_t(c) % w) + w) % w); };
  const uint32_t r0 = uint32_t(y0), r1 = std::min(r0 + 1, latLong.height - 1);
  glm::dvec3 sum(0.0);
  for (int c = 0; c < 3; ++c) {
    const double a = latLong.pixel(col(x0), r0)[c], b = latLong.pixel(col(x0 + 1), r0)[c];
    const double e = latLong.pixel(col(x0), r1)[c], f = latLong.pixel(col(x0 + 1), r1)[c];
    sum[c] = (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * e + fx * f);
  }
  return sum;
}

HemisphereMap hemisphereFromLatLong(const core::ImageF& latLong, double azimuthDegrees,
                                    uint32_t cols, uint32_t rows, uint32_t supersample) {
  checkLatLong(latLong);
  if (cols == 0 || rows == 0 || supersample == 0)
    throw std::invalid_argument("hemisphere map: cols, rows and supersample must be at least 1");
  HemisphereMap map{core::ImageF(cols, rows)};
  const double turn = azimuthDegrees / 360.0;
  const double n = double(supersample) * supersample;
  for (uint32_t row = 0; row < rows; ++row)
    for (uint32_t colIndex = 0; colIndex < cols; ++colIndex) {
      glm::dvec3 sum(0.0);
      for (uint32_t sy = 0; sy < supersample; ++sy)
        for (uint32_t sx = 0; sx < supersample; ++sx) {
          const double u = (row + (sy + 0.5) / supersample) / rows;
          const double t = (colIndex + (sx + 0.5) / supersample) / cols - turn;
          sum += sampleLatLong(latLong, diskToHemisphere({u, t - std::floor(t)}));
        }
      float* p = map.radiance.pixel(colIndex, row);
      for (int c = 0; c < 3; ++c) p[c] = float(sum[c] / n);
    }
  return map;
}

core::ImageF shrinkLatLong(const core::ImageF& latLong, uint32_t factor) {
  checkLatLong(latLong);
  if (factor == 0 || latLong.width % factor || latLong.height % factor)
    throw std::invalid_argument("lat-long map: " + std::to_string(latLong.width) + " × " +
                                std::to_string(latLong.height) + " is not a multiple of " +
                                std::to_string(factor));
  core::ImageF out(latLong.width / factor, latLong.height / factor);
  for (uint32_t y = 0; y < out.height; ++y)
    for (uint32_t x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (uint32_t j = 0; j < factor; ++j)
          for (uint32_t i = 0; i < factor; ++i)
            sum += latLong.pixel(x * factor + i, y * factor + j)[c];
        out.pixel(x, y)[c] = float(sum / (double(factor) * factor));
      }
  return out;
}

}  // namespace penumbra::envmap
