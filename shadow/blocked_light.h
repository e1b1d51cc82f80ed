// The light a placed product may block (design §1, per frame steps 4-5): the shaft
// hierarchy's traversal with the product's bounding box gives the sources it may occlude
// and the receiver patches that may see it happen (Gibson 2003 §6.1), and the frame-rate
// controller's pass count cuts the source KD-tree into at most that many clusters that
// together stand for every blocked source exactly once (§8). The algorithms live in
// shadow/shaft_hierarchy.h and shadow/source_clusters.h; this stage runs them in order and
// times them. Cost: tens of microseconds; no allocation once used.
#pragma once

#include <cstddef>
#include <cstdint>

#include "scene/patch_mesh.h"
#include "shadow/shaft_hierarchy.h"
#include "shadow/source_clusters.h"

namespace penumbra::shadow {

struct BlockedLight {
  // §6.1 and §8 for the product in `bounds`, with at most `passes` clusters (split by
  // transfer × angular size from `bounds`: selectSourceClusters). `frame` must
  // change from call to call (the §6.1 frame tags).
  void find(const ShaftHierarchy& hierarchy, const scene::Aabb& bounds, uint32_t frame,
            size_t passes);

  TraversalResult traversal;                // sources and receiver patches (§6.1)
  ClusterSelection selection;               // clusters covering traversal.sources (§8)
  int64_t nsTraversal = 0, nsClusters = 0;  // wall time of each
};

}  // namespace penumbra::shadow
