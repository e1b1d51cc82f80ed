#include "shadow/cluster_map_size.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "scene/camera.h"

namespace penumbra::shadow {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// `p` in pixels of a view `width` x `height` through `viewProj` (relative to the image centre),
// or nullopt when it is not in front of the camera (the clip w of a point the camera looks at is
// its depth along the view axis; the near plane is well beyond a millimetre).
std::optional<glm::dvec2> toPixels(const glm::dmat4& viewProj, uint32_t width, uint32_t height,
                                   const glm::dvec3& p) {
  const glm::dvec4 clip = viewProj * glm::dvec4(p, 1.0);
  if (!(clip.w > 1e-3)) return std::nullopt;
  return glm::dvec2(0.5 * width * (clip.x / clip.w), 0.5 * height * (clip.y / clip.w));
}

}  // namespace

double shadowFootprintPx(const raster::StaticView& view, const LightFrustum& frustum,
                         const glm::dvec3& light, const scene::Aabb& room) {
  const glm::dvec3 axis = glm::normalize(frustum.sphereCentre - light);
  const double toCentre = glm::length(frustum.sphereCentre - light);
  // Where the axis leaves the box: the nearest of the far planes it heads for.
  double exit = kInfinity;
  int face = -1;
  for (int i = 0; i < 3; ++i) {
    if (axis[i] == 0) continue;
    const double t = ((axis[i] > 0 ? room.max[i] : room.min[i]) - light[i]) / axis[i];
    if (t < exit) {
      exit = t;
      face = i;
    }
  }
  if (face < 0 || !std::isfinite(exit)) return kInfinity;
  // A product reaching out of the box: its shadow is no nearer than the product itself.
  const double distance = std::max(exit, toCentre);
  const glm::dvec3 x = light + distance * axis;
  const double half = frustum.tanHalfFovY * distance;
  glm::dvec3 normal(0.0);
  normal[face] = 1.0;
  // e2 lies in the face and across the axis; e1 is the window's other direction.
  glm::dvec3 across = glm::cross(axis, normal);
  if (glm::length(across) < 1e-9) across = glm::cross(axis, leastAlignedAxis(axis));
  const glm::dvec3 e2 = glm::normalize(across);
  const glm::dvec3 e1 = glm::cross(e2, axis);
  // The ray from the light through the window's point q, met with the face's plane.
  const double facing = glm::dot(normal, x - light);
  const auto onFace = [&](const glm::dvec3& q) -> std::optional<glm::dvec3> {
    const double along = glm::dot(normal, q - light);
    // Grazing (or heading away from the face): the footprint is unbounded.
    if (!(along * facing > 0) || std::abs(facing / along) > 1e3) return std::nullopt;
    return light + (facing / along) * (q - light);
  };
  const glm::dmat4 viewProj = scene::fromRasterMat4(view.cameraViewProj);
  const auto span = [&](const std::optional<glm::dvec3>& a,
                        const std::optional<glm::dvec3>& b) -> double {
    if (!a || !b) return kInfinity;
    const auto pa = toPixels(viewProj, view.width, view.height, *a);
    const auto pb = toPixels(viewProj, view.width, view.height, *b);
    if (!pa || !pb) return kInfinity;
    return glm::length(*pa - *pb);
  };
  const double unstretched = span(x + half * e2, x - half * e2);
  const double tilted = span(onFace(x + half * e1), onFace(x - half * e1));
  return std::max(unstretched, tilted);
}

uint32_t clusterMapSize(double footprintPx, double texelsPerPixel, uint32_t frameSize) {
  if (!(texelsPerPixel > 0) || !(footprintPx < 1e9)) return frameSize;
  const double need = std::ceil(texelsPerPixel * footprintPx / 16.0) * 16.0;
  const double floor = std::min<double>(kMinClusterMapSize, frameSize);
  return static_cast<uint32_t>(std::clamp(need, floor, double(frameSize)));
}

}  // namespace penumbra::shadow
