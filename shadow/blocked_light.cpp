#include "shadow/blocked_light.h"

#include "core/clock.h"

namespace penumbra::shadow {

void BlockedLight::find(const ShaftHierarchy& hierarchy, const scene::Aabb& bounds, uint32_t frame,
                        size_t passes) {
  core::Stopwatch watch;
  hierarchy.traverse(bounds, frame, traversal);
  nsTraversal = watch.lapNs();
  selectSourceClusters(hierarchy, traversal.sources, frame, passes, selection, &bounds);
  nsClusters = watch.lapNs();
}

}  // namespace penumbra::shadow
