#include "shadow/patch_transfer.h"

namespace penumbra::shadow {

glm::dvec3 unshadowedTransfer(const glm::dvec3& x, const glm::dvec3& n,
                              const glm::dvec3& reflectance, const glm::dvec3& emission,
                              const glm::dvec3& centre, const glm::dvec3& normal, double area) {
  return reflectance * emission * scene::pointToPatchFormFactor(x, n, centre, normal, area);
}

}  // namespace penumbra::shadow
