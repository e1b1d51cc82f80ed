#include "lighting/form_factor.h"

#include <cmath>
#include <numbers>

namespace penumbra::lighting {

std::vector<glm::dvec3> clipPolygonToHemisphere(const glm::dvec3& x, const glm::dvec3& n,
                                                std::span<const glm::dvec3> polygon) {
  std::vector<glm::dvec3> out;
  const size_t count = polygon.size();
  out.reserve(count + 1);
  for (size_t k = 0; k < count; ++k) {
    const glm::dvec3& a = polygon[k];
    const glm::dvec3& b = polygon[(k + 1) % count];
    const double da = glm::dot(n, a - x), db = glm::dot(n, b - x);
    if (da >= 0) out.push_back(a);
    // A strict sign change only: an edge ending on the plane adds its end point when that
    // vertex is visited, so no vertex is emitted twice.
    if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
      const double t = da / (da - db);
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

double pointToPolygonFormFactor(const glm::dvec3& x, const glm::dvec3& n,
                                std::span<const glm::dvec3> polygon) {
  if (polygon.size() < 3) return 0;
  const std::vector<glm::dvec3> clipped = clipPolygonToHemisphere(x, n, polygon);
  if (clipped.size() < 3) return 0;
  double sum = 0;
  const size_t count = clipped.size();
  for (size_t k = 0; k < count; ++k) {
    const glm::dvec3 r0 = clipped[k] - x;
    const glm::dvec3 r1 = clipped[(k + 1) % count] - x;
    const glm::dvec3 c = glm::cross(r0, r1);
    const double s = glm::length(c);
    // A zero cross product is an edge pointing at x (or a vertex at x): it subtends no
    // angle and contributes nothing.
    if (!(s > 0)) continue;
    // atan2(|r0 x r1|, r0 . r1) rather than acos of the normalised dot product: acos
    // loses half its digits for the small angles far-away patches subtend.
    const double beta = std::atan2(s, glm::dot(r0, r1));
    sum += beta * glm::dot(n, c) / s;
  }
  // The sum is the signed projected solid angle of the clipped polygon; reversing the
  // winding negates it, so its magnitude is the form factor either way round.
  return std::abs(sum) / (2.0 * std::numbers::pi);
}

}  // namespace penumbra::lighting
