// Frame-rate control by source clusters (Gibson 2003 §8, Figs. 5–6): when there is time
// for only n shadow passes but N > n sources may be occluded, cut the source KD-tree so
// that n nodes together cover every occluded source exactly once, and cast one shadow map
// per node from the centre of its most energetic occluded patch.
//
// Per frame: the frame tag is pushed from each occluded leaf towards the root, marking
// the branches that hold occluded sources (Fig. 5b); starting from the root, the marked
// node with the largest average transfer is replaced by its marked children until there
// are n nodes or only leaves remain (Fig. 6). The frame loop ranks by that transfer times
// the node's angular size from the product instead (selectSourceClusters, `occluder`).
//
// Invariants:
//   - Energy: the clusters' source lists partition the occluded set (each occluded source
//     in exactly one cluster); a cluster lists only occluded leaves, never the unoccluded
//     siblings that share its node.
//   - n >= number of occluded sources gives one cluster per source (the per-patch list).
//   - Deterministic whatever the order of `occludedSources`: ties break on node and source
//     indices, sums run in a fixed order.
//   - A cluster is keyed in the §8 list by its node's average transfer over all its leaves
//     (the paper's rule, Fig. 6), but it subtracts only its occluded leaves' light:
//     occludedTransfer, never nodeTransfer, is what its pass carries.
// Cost: O(N log S) for the tags, O(n log n) for the selection, no allocation once a
// ClusterSelection has been used once with this hierarchy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {

// One representative source (§8): a node of the source KD-tree standing for its occluded
// leaves.
struct SourceCluster {
  uint32_t node = 0;  // index into ShaftHierarchy::sourceNodes()
  // The occluded source (index into SourceReceiverSets::sources) with the largest
  // sourceAverage: §8 (last paragraph) casts the shadow map from its patch centre;
  // PassList casts it from the cluster's centroid (PassList::clusterCentroid).
  uint32_t representative = 0;
  // The cluster's occluded sources are ClusterSelection::sources[firstSource, +sourceCount),
  // by decreasing sourceAverage (ties: lower index first); the first is `representative`.
  uint32_t firstSource = 0;
  uint32_t sourceCount = 0;
  double nodeTransfer = 0;      // the node's average transfer, over all its leaves (§8 key)
  double occludedTransfer = 0;  // sum of sourceAverage over the cluster's occluded sources
};

// Scratch state owned by selectSourceClusters(); keep it between frames, do not touch it.
struct ClusterScratch {
  std::vector<uint32_t> nodeTag;  // per source node: the frame that marked it
  std::vector<double> nodeKey;    // per source node: its split key, set when it is listed
  std::vector<uint32_t> open;     // the §8 list's expandable nodes (a binary heap)
  std::vector<uint32_t> done;     // the list's leaves
  std::vector<uint32_t> stack;
  uint32_t lastFrame = 0;
  bool primed = false;
};

struct ClusterSelection {
  // By decreasing occludedTransfer (ties: lower representative index first): the §7.1.1
  // order in which the clusters' passes should run.
  std::vector<SourceCluster> clusters;
  std::vector<uint32_t> sources;  // the clusters' source lists, back to back
  ClusterScratch scratch;
};

// §8: at most `n` clusters covering `occludedSources` (indices into
// SourceReceiverSets::sources, e.g. TraversalResult::sources; a repeated index counts
// once). Without `occluder` a node is split by its average transfer (the paper's Fig. 6);
// with the occluder's bounds, by average transfer × node diameter / distance from the
// occluder's centre, which grows with the light a single shadow map misplaces (the
// argument is at the code). Fewer than n when fewer sources are occluded; none when n = 0
// or nothing is occluded. `frame` follows the rule of ShaftHierarchy::traverse(): a new number per
// call (a repeat is detected and costs a tag reset). Throws std::out_of_range for a source index >=
// hierarchy.sourceCount().
void selectSourceClusters(const ShaftHierarchy& hierarchy,
                          std::span<const uint32_t> occludedSources, uint32_t frame, size_t n,
                          ClusterSelection& out, const scene::Aabb* occluder = nullptr);

}  // namespace penumbra::shadow
