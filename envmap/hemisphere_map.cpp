#include "envmap/hemisphere_map.h"

#include <cmath>
#include <numbers>

#include "scene/portable_trig.h"

namespace penumbra::envmap {

DiskPolar concentricSquareToDisk(double s, double t) {
  // Shirley & Chiu 1997, with the azimuth written in turns per wedge so that no π enters:
  // in the wedge |a| > |b| the azimuth is (1/8)·(b/a) turns from the wedge's axis.
  const double a = 2.0 * s - 1.0;
  const double b = 2.0 * t - 1.0;
  if (a == 0.0 && b == 0.0) return {0.0, 0.0};
  double r = 0, turns = 0;
  if (std::fabs(a) > std::fabs(b)) {
    r = std::fabs(a);
    turns = (a > 0 ? 0.0 : 0.5) + 0.125 * (b / a);
  } else {
    r = std::fabs(b);
    turns = (b > 0 ? 0.25 : 0.75) - 0.125 * (a / b);
  }
  if (turns < 0.0) turns += 1.0;
  if (turns >= 1.0) turns -= 1.0;
  return {r * r, turns};
}

glm::dvec3 diskToHemisphere(const DiskPolar& p) {
  // r·√(2 − r²) = √(u (2 − u)) = sin θ for z = 1 − u = cos θ (Havran 2005 §3.1).
  const double sinTheta = std::sqrt(p.u * (2.0 - p.u));
  double sinPhi = 0, cosPhi = 0;
  scene::sinCosDegrees(360.0 * p.turns, sinPhi, cosPhi);
  return {sinTheta * cosPhi, sinTheta * sinPhi, 1.0 - p.u};
}

double HemisphereMap::pixelSolidAngle() const {
  return 2.0 * std::numbers::pi / (double(rows()) * double(cols()));
}

glm::dvec3 HemisphereMap::pixelCentre(uint32_t col, uint32_t row) const {
  return diskToHemisphere({(row + 0.5) / rows(), (col + 0.5) / cols()});
}

}  // namespace penumbra::envmap
