#include "shadow/area_penumbra.h"

#include <algorithm>
#include <cmath>

namespace penumbra::shadow {

double clusterHalfWidth(const SceneBundle& bundle, const SourceCluster& cluster,
                        std::span<const uint32_t> sources, const glm::dvec3& light,
                        const glm::dvec3& axis) {
  double variance = 0, weight = 0;
  for (uint32_t i = cluster.firstSource; i < cluster.firstSource + cluster.sourceCount; ++i) {
    const uint32_t source = sources[i];
    const PatchRecord& patch = bundle.patches[bundle.sets.sources[source]];
    const double w = std::max(double(bundle.transfers.sourceAverage[source]), 1e-12);
    const glm::dvec3 delta = glm::dvec3(patch.centre) - light;
    const double along = glm::dot(delta, axis);
    // Per axis across the view: the patch's own a² / 12 and half its offset's square.
    variance += w * (double(patch.area) / 12.0 + 0.5 * (glm::dot(delta, delta) - along * along));
    weight += w;
  }
  return weight > 0 ? std::sqrt(3.0 * variance / weight) : 0.0;
}

double penumbraScale(const LightFrustum& frustum, double halfWidth, uint32_t mapSize) {
  const double n = frustum.zNear, f = frustum.zFar;
  if (frustum.orthographic || !(frustum.tanHalfFovY > 0) || !(n > 0) || !(f > n)) return 0;
  return halfWidth * double(mapSize) * (f - n) / (2.0 * frustum.tanHalfFovY * f * n);
}

}  // namespace penumbra::shadow
