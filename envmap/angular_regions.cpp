#include "envmap/angular_regions.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scene/portable_trig.h"

namespace penumbra::envmap {

namespace {

// arccos in degrees for c in [−1, 1]: 64 halvings of [0°, 180°] (cosine decreases there).
double arccosDegrees(double c) {
  double lo = 0, hi = 180;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    double s = 0, cosine = 0;
    scene::sinCosDegrees(mid, s, cosine);
    (cosine > c ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

glm::dvec3 unit(const glm::dvec3& v) {
  return v / std::sqrt(glm::dot(v, v));
}

}  // namespace

AngularRegions::AngularRegions(uint32_t regions, uint32_t cubeSize) : cubeSize_(cubeSize) {
  if (regions < 2 || cubeSize == 0)
    throw std::invalid_argument("angular regions: at least 2 regions and a cube size of 1");
  // Fibonacci sphere: z at the centres of `regions` equal-area bands, azimuth stepping by the
  // golden angle 360° (2 − φ) = 137.507764…°.
  constexpr double kGoldenAngle = 137.50776405003785;
  for (uint32_t i = 0; i < regions; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / regions;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    double s = 0, c = 0;
    scene::sinCosDegrees(std::fmod(kGoldenAngle * i, 360.0), s, c);
    centres_.push_back({r * c, r * s, z});
  }
  // The cube map: each texel's nearest centre (largest dot product, ties to the lower index),
  // and the two angles that bound ρ.
  cube_.resize(size_t(6) * cubeSize * cubeSize);
  double minCentreDot = 1, minCornerDot = 1;
  for (uint32_t face = 0; face < 6; ++face)
    for (uint32_t j = 0; j < cubeSize; ++j)
      for (uint32_t i = 0; i < cubeSize; ++i) {
        const glm::dvec3 d = texelDirection(face, (i + 0.5) / cubeSize, (j + 0.5) / cubeSize);
        uint32_t best = 0;
        double bestDot = -2;
        for (uint32_t k = 0; k < regions; ++k)
          if (const double dot = glm::dot(d, centres_[k]); dot > bestDot) bestDot = dot, best = k;
        cube_[(size_t(face) * cubeSize + j) * cubeSize + i] = best;
        minCentreDot = std::min(minCentreDot, bestDot);
        for (int corner = 0; corner < 4; ++corner) {
          const glm::dvec3 e = texelDirection(face, double(i + (corner & 1)) / cubeSize,
                                              double(j + (corner >> 1)) / cubeSize);
          minCornerDot = std::min(minCornerDot, glm::dot(d, e));
        }
      }
  radiusDegrees_ = arccosDegrees(minCentreDot) + arccosDegrees(minCornerDot);
  double sinRho = 0, cosRho = 0;
  scene::sinCosDegrees(std::min(radiusDegrees_, 90.0), sinRho, cosRho);
  minDot_ = -sinRho;
}

// Face f: major axis f / 2 (x, y, z), sign + for even f; (s, t) in [0, 1]² across the face.
glm::dvec3 AngularRegions::texelDirection(uint32_t face, double s, double t) const {
  const double a = 2 * s - 1, b = 2 * t - 1, sign = face % 2 == 0 ? 1.0 : -1.0;
  switch (face / 2) {
    case 0:
      return unit({sign, a, b});
    case 1:
      return unit({a, sign, b});
    default:
      return unit({a, b, sign});
  }
}

uint32_t AngularRegions::texelOf(const glm::dvec3& d) const {
  const double ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  uint32_t face = 0;
  double a = 0, b = 0, m = 0;
  if (ax >= ay && ax >= az) {
    face = d.x >= 0 ? 0 : 1, a = d.y, b = d.z, m = ax;
  } else if (ay >= az) {
    face = d.y >= 0 ? 2 : 3, a = d.x, b = d.z, m = ay;
  } else {
    face = d.z >= 0 ? 4 : 5, a = d.x, b = d.y, m = az;
  }
  const auto cell = [&](double v) {
    return std::min(cubeSize_ - 1, uint32_t(std::max(0.0, (v / m + 1) * 0.5 * cubeSize_)));
  };
  return (face * cubeSize_ + cell(b)) * cubeSize_ + cell(a);
}

uint32_t AngularRegions::regionOf(const glm::dvec3& normal) const {
  return cube_[texelOf(normal)];
}

std::vector<std::vector<uint32_t>> AngularRegions::assign(const LightSet& lights) const {
  std::vector<std::vector<uint32_t>> lists(centres_.size());
  for (uint32_t r = 0; r < centres_.size(); ++r)
    for (uint32_t i = 0; i < lights.size(); ++i)
      if (glm::dot(centres_[r], lights[i].direction) > minDot_) lists[r].push_back(i);
  return lists;
}

}  // namespace penumbra::envmap
