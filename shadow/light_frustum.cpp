#include "shadow/light_frustum.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "scene/camera.h"

namespace penumbra::shadow {

std::optional<LightFrustum> fitLightFrustum(const glm::dvec3& source,
                                            const scene::Aabb& occluderBounds, double farDistance) {
  if (occluderBounds.empty()) return std::nullopt;
  const glm::dvec3 centre = occluderBounds.centre();
  const double radius = 0.5 * glm::length(occluderBounds.size());
  const glm::dvec3 toCentre = centre - source;
  const double dist = glm::length(toCentre);
  if (!std::isfinite(dist) || !std::isfinite(radius) || !(dist > radius)) return std::nullopt;

  // The cone from the source tangent to the sphere has half-angle asin(R / d); a square
  // map whose half field of view is that angle inscribes the cone's circle, so the whole
  // sphere (and the box inside it) projects inside the map. The 1e-6 widening absorbs the
  // float rounding of the matrix without moving silhouettes by a visible fraction of a
  // texel (1e-6 of 128 texels).
  const double tanHalf = radius / std::sqrt(dist * dist - radius * radius) * (1.0 + 1e-6);
  // Just in front of the sphere; 0.1% keeps its nearest point off the near plane after
  // rounding. The far plane must lie beyond the near one whatever the caller passes.
  const double zNear = std::max((dist - radius) * 0.999, kMinLightNear);
  const double zFar = std::max(farDistance, dist + radius + zNear);

  // Up: the world axis least aligned with the view direction, so lookAt never degenerates
  // (a ceiling light looking straight down at the object).
  const glm::dvec3 f = toCentre / dist;
  const glm::dvec3 absF = glm::abs(f);
  glm::dvec3 up(0, 0, 1);
  if (absF.x <= absF.y && absF.x <= absF.z) {
    up = glm::dvec3(1, 0, 0);
  } else if (absF.y <= absF.z) {
    up = glm::dvec3(0, 1, 0);
  }

  LightFrustum out;
  out.viewProj =
      scene::perspectiveFromTanHalf(tanHalf, 1.0, zNear, zFar) * scene::lookAt(source, centre, up);
  out.rasterViewProj = scene::toRasterMat4(out.viewProj);
  out.sphereCentre = centre;
  out.sphereRadius = radius;
  out.zNear = zNear;
  out.zFar = zFar;
  out.tanHalfFovY = tanHalf;
  return out;
}

bool triangleMayReceive(const glm::dmat4& lightViewProj, const glm::dvec3& a, const glm::dvec3& b,
                        const glm::dvec3& c) {
  const std::array<glm::dvec4, 3> clip = {lightViewProj * glm::dvec4(a, 1.0),
                                          lightViewProj * glm::dvec4(b, 1.0),
                                          lightViewProj * glm::dvec4(c, 1.0)};
  // Signed distances to w + x >= 0, w - x >= 0, w + y, w - y, w + z (near), w - z (far).
  for (int plane = 0; plane < 6; ++plane) {
    const int axis = plane / 2;
    const double sign = plane % 2 == 0 ? 1.0 : -1.0;
    bool allOutside = true;
    for (const glm::dvec4& p : clip) {
      if (p.w + sign * p[axis] >= 0) {
        allOutside = false;
        break;
      }
    }
    if (allOutside) return false;
  }
  return true;
}

}  // namespace penumbra::shadow
