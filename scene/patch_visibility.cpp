#include "scene/patch_visibility.h"

#include <stdexcept>

namespace penumbra::scene {

std::vector<uint8_t> visiblePatches(const PatchMesh& mesh, const Camera& camera, int width,
                                    int height, const RoomDescription* room) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("visiblePatches: empty image");
  const glm::dmat4 viewProj = camera.viewProj();
  const glm::dvec3 eye = camera.eye;
  // Inside the image: clip-space x, y within [-w, w] with w > 0 (in front of the eye).
  // The far plane is ignored: a wall beyond zFar is still seen by the real camera.
  auto inImage = [&](const glm::dvec3& p) {
    const glm::dvec4 clip = viewProj * glm::dvec4(p, 1.0);
    return clip.w > 0 && clip.x >= -clip.w && clip.x <= clip.w && clip.y >= -clip.w &&
           clip.y <= clip.w;
  };
  auto unoccluded = [&](const glm::dvec3& p) {
    if (room == nullptr) return true;
    const glm::dvec3 d = p - eye;
    const double dist = glm::length(d);
    if (!(dist > 0)) return false;
    // Stop a hair short of the point itself, whose own quad lies at t = dist.
    return !room->intersect(eye, d / dist, 1e-9, dist * (1.0 - 1e-7)).has_value();
  };
  std::vector<uint8_t> visible(mesh.patches.size(), 0);
  for (size_t i = 0; i < mesh.patches.size(); ++i) {
    const Patch& patch = mesh.patches[i];
    if (!(glm::dot(patch.normal, eye - patch.centre) > 0)) continue;  // back side
    // The patch's corners: the vertices of its two triangles (four distinct ones).
    glm::dvec3 samples[5] = {patch.centre, patch.centre, patch.centre, patch.centre, patch.centre};
    int n = 1;
    for (uint32_t t = patch.firstTriangle; t < patch.firstTriangle + 2 && n < 5; ++t) {
      for (int k = 0; k < 3 && n < 5; ++k) {
        const glm::dvec3 corner = mesh.positions[mesh.indices[3 * t + k]];
        const glm::dvec3 s = 0.5 * (patch.centre + corner);
        bool dup = false;
        for (int m = 1; m < n; ++m) dup = dup || glm::length(samples[m] - s) < 1e-12;
        if (!dup) samples[n++] = s;
      }
    }
    for (int k = 0; k < n; ++k) {
      if (inImage(samples[k]) && unoccluded(samples[k])) {
        visible[i] = 1;
        break;
      }
    }
  }
  return visible;
}

}  // namespace penumbra::scene
