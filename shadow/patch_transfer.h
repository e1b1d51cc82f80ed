// The radiance transfer from one emitting patch to a surface point, unshadowed (Gibson 2003
// §5): L_ij = reflectance x L_j x F(x, n -> j), with F the point-to-patch form factor
// (scene::pointToPatchFormFactor). Visibility is the caller's: the product's shading keeps it
// unshadowed (self-shadowing comes from the shadow passes, §7.2); the synthetic traces of
// data/traces multiply it by a ray-cast visibility. One expression, so both round the same
// way: (reflectance * emission) * F, component-wise.
#pragma once

#include <glm/glm.hpp>

#include "scene/patch_mesh.h"

namespace penumbra::shadow {

// Zero where the point and the patch do not face each other (F = 0).
glm::dvec3 unshadowedTransfer(const glm::dvec3& x, const glm::dvec3& n,
                              const glm::dvec3& reflectance, const glm::dvec3& emission,
                              const glm::dvec3& centre, const glm::dvec3& normal, double area);

inline glm::dvec3 unshadowedTransfer(const glm::dvec3& x, const glm::dvec3& n,
                                     const glm::dvec3& reflectance, const scene::Patch& patch) {
  return unshadowedTransfer(x, n, reflectance, patch.emission, patch.centre, patch.normal,
                            patch.area);
}

}  // namespace penumbra::shadow
