#include "shadow/light_frustum.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/camera.h"

namespace penumbra::shadow {

glm::dvec3 leastAlignedAxis(const glm::dvec3& f) {
  const glm::dvec3 absF = glm::abs(f);
  if (absF.x <= absF.y && absF.x <= absF.z) return {1, 0, 0};
  if (absF.y <= absF.z) return {0, 1, 0};
  return {0, 0, 1};
}

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
  LightFrustum out;
  out.viewProj = scene::perspectiveFromTanHalf(tanHalf, 1.0, zNear, zFar) *
                 scene::lookAt(source, centre, leastAlignedAxis(toCentre / dist));
  out.rasterViewProj = scene::toRasterMat4(out.viewProj);
  out.sphereCentre = centre;
  out.sphereRadius = radius;
  out.zNear = zNear;
  out.zFar = zFar;
  out.tanHalfFovY = tanHalf;
  return out;
}

std::optional<LightFrustum> fitDirectionalFrustum(const glm::dvec3& towardsLight,
                                                  const scene::Aabb& occluderBounds,
                                                  const scene::Aabb& room) {
  if (occluderBounds.empty() || room.empty()) return std::nullopt;
  const double length = glm::length(towardsLight);
  const glm::dvec3 centre = occluderBounds.centre();
  const double radius = 0.5 * glm::length(occluderBounds.size());
  if (!std::isfinite(length) || !(length > 0) || !std::isfinite(radius) ||
      !std::isfinite(centre.x + centre.y + centre.z)) {
    return std::nullopt;
  }
  const glm::dvec3 d = towardsLight / length;
  // The eye one diameter out on the light's side (a point product still gets a 1 cm gap):
  // the sphere spans distances [eye - R, eye + R] from it.
  const double back = 2.0 * radius + 0.01;
  const glm::dvec3 eye = centre + back * d;
  // Just in front of the sphere (0.1% margin against rounding, as fitLightFrustum); beyond
  // the farthest room corner along the view, and beyond the sphere in any case.
  const double zNear = (back - radius) * 0.999;
  double zFar = back + radius + zNear;
  for (size_t corner = 0; corner < 8; ++corner) {
    zFar = std::max(zFar, glm::dot(eye - room.corner(corner), d) + 0.01);
  }
  // The window: the occluder's box projected across the light, plus 3% of its extent on each
  // side (PCF's 2 × 2 taps and the float rounding of the matrix stay inside the map). Not
  // the bounding sphere's square: seen from above, the chair's box covers a fifth of it, so
  // the map's texels are ~2.2× denser on a side (geometry: 0.5 m square against 1.14 m). A
  // receiver wholly outside the window is outside the map (M = 0, spec §7): it cannot be
  // shadowed, as no occluder texel lies beyond the box.
  const glm::dmat4 view = scene::lookAt(eye, centre, leastAlignedAxis(-d));
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (size_t corner = 0; corner < 8; ++corner) {
    const glm::dvec4 q = view * glm::dvec4(occluderBounds.corner(corner), 1.0);
    lo = glm::min(lo, glm::dvec2(q));
    hi = glm::max(hi, glm::dvec2(q));
  }
  const glm::dvec2 margin = 0.03 * (hi - lo) + 1e-4;  // 0.1 mm for a flat or point product
  lo -= margin;
  hi += margin;
  LightFrustum out;
  out.viewProj = glm::ortho(lo.x, hi.x, lo.y, hi.y, zNear, zFar) * view;
  out.rasterViewProj = scene::toRasterMat4(out.viewProj);
  out.sphereCentre = centre;
  out.sphereRadius = radius;
  out.zNear = zNear;
  out.zFar = zFar;
  out.orthographic = true;
  return out;
}

uint8_t clipOutcode(const glm::dmat4& lightViewProj, const glm::dvec3& p) {
  const glm::dvec4 clip = lightViewProj * glm::dvec4(p, 1.0);
  uint8_t code = 0;
  for (int plane = 0; plane < 6; ++plane) {
    const double sign = plane % 2 == 0 ? 1.0 : -1.0;
    if (!(clip.w + sign * clip[plane / 2] >= 0)) code |= uint8_t(1u << plane);
  }
  return code;
}

bool triangleMayReceive(const glm::dmat4& lightViewProj, const glm::dvec3& a, const glm::dvec3& b,
                        const glm::dvec3& c) {
  // All three outside one plane: that plane's bit survives the AND.
  return (clipOutcode(lightViewProj, a) & clipOutcode(lightViewProj, b) &
          clipOutcode(lightViewProj, c)) == 0;
}

}  // namespace penumbra::shadow
