#include "scene/shadow_boundary_refinement.h"

#include <algorithm>
#include <array>
#include <utility>

namespace penumbra::scene {

ShadowBoundaryTest::ShadowBoundaryTest(const RoomDescription& room, std::vector<LightSample> lights,
                                       double significance)
    : room_(room), lights_(std::move(lights)), significance_(significance) {}

bool ShadowBoundaryTest::straddles(const Quad& quad, double s0, double s1, double t0,
                                   double t1) const {
  constexpr size_t kPoints = 9;
  constexpr double kNormalOffset = 1e-4;  // metres, as lighting/radiance_transfer.h
  const double sm = 0.5 * (s0 + s1), tm = 0.5 * (t0 + t1);
  const glm::dvec3 n = quad.normal();
  const std::array<glm::dvec3, kPoints> points = {
      quad.point(s0, t0), quad.point(s1, t0), quad.point(s0, t1),
      quad.point(s1, t1), quad.point(sm, t0), quad.point(sm, t1),
      quad.point(s0, tm), quad.point(s1, tm), quad.point(sm, tm)};
  std::array<double, kPoints> seen{};
  double disputed = 0;  // light whose visibility differs between the points
  for (const LightSample& light : lights_) {
    double most = 0;
    bool lit = false, hidden = false;
    for (size_t k = 0; k < kPoints; ++k) {
      const glm::dvec3 x = points[k] + kNormalOffset * n;
      const double arriving =
          pointToPatchFormFactor(x, n, light.centre, light.normal, light.area) * light.power;
      // A light behind the surface needs no ray: its form factor already fades to 0 at the
      // horizon, smoothly, so it is neither side of a shadow boundary.
      if (!(arriving > 0)) continue;
      if (room_.segmentBlocked(x, light.centre)) {
        hidden = true;
      } else {
        lit = true;
        seen[k] += arriving;
      }
      most = std::max(most, arriving);
    }
    if (lit && hidden) disputed += most;
  }
  return disputed > significance_ * *std::max_element(seen.begin(), seen.end());
}

}  // namespace penumbra::scene
