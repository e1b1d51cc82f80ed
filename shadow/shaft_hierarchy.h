// The shaft hierarchy of Gibson 2003 §6: a coarse, pruned subdivision of the line space
// between the source patches and the receiver patches, which answers once per frame
// "which sources can the object's bounding box occlude, and which receivers can it
// shadow?" (§6.1). Fine occlusion is left to the shadow maps (§7).
//
// Inputs: the patch mesh, the source/receiver sets and the sparse radiance transfers of
// light_transport.h. Three trees are built once:
//   - a receiver octree, top-down, at most `maxReceiversPerLeaf` patches per leaf (§6);
//   - a binary source KD-tree down to single patches (§6), whose nodes carry the summed
//     average transfer that §8 ranks clusters by;
//   - the shaft hierarchy: a shaft joins one source node and one receiver node and holds
//     the Haines–Wallace 1994 shaft (their joint bounding box plus the planes through
//     corresponding box edges). Built from the pair of roots down, a shaft is split on its
//     larger node until both nodes are leaves; §6 ends the recursion at an insignificant
//     shaft, one whose sources send T(s, v) < pruneFraction x L_v to every vertex v of its
//     receiver node (luminances). Such a shaft is pruned when, at every v, the light
//     already pruned there plus T(s, v) stays below pruneFraction x L_v, and T(s, v) is
//     then charged to every v; otherwise it is kept as a coarse leaf, which reports every
//     source and receiver of its two nodes. A significant shaft whose children are all
//     insignificant ends there too, as one coarse leaf rather than up to 8. Pruning every
//     insignificant shaft, as this hierarchy did before issue 15, has no bound on the
//     light lost: with many small sources (a ceiling panel of 100 patches, ~1% of a
//     vertex's light each) siblings under 2% go one after another, and a third of a
//     vertex's light or more with them (33% in the tests' panel room, 43% in the shipped
//     showroom). The budget bounds it (ShaftBuildOptions::boundLostLight).
//
// Invariants:
//   - Conservative: every segment from a point of a source patch to a point of a receiver
//     patch lies in the convex hull of the two patch boxes, which every shaft on its path
//     contains (the planes' offsets are the maximum over both boxes' corners plus a
//     margin), so traverse() never misses a (source, receiver) pair an object box can cut,
//     unless the pair is unreported (below): none when pruneFraction = 0, and never a pair
//     carrying >= pruneFraction of L_i at a vertex of the receiver (only insignificant
//     shafts are pruned).
//   - Bounded loss (boundLostLight): call a pair (source j, receiver patch p) unreported
//     when no leaf shaft joins a source node holding j to a receiver node holding p. At
//     every receiver vertex v, the transfers L_vj of the sources j unreported with at
//     least one receiver patch around v sum to at most pruneFraction x L_v (luminances, up
//     to rounding): an object covering every source leaves at most that much light in its
//     umbra. Proof: the shafts of the unpruned hierarchy over (j, p) form one chain from
//     the root to the shaft (j's leaf, p's leaf), as each split partitions one node's
//     sources or patches. Down that chain the build meets either a kept leaf shaft, which
//     reports (j, p), or a pruned shaft P = (s, r), and then exactly one (a kept shaft is
//     either a leaf or split into children that are all built or pruned; nothing below P
//     is built). So j is under s and v is a vertex of r, and pruning P charged
//     T(s, v) = sum of L_vi over the sources i under s (>= L_vj, transfers being
//     non-negative) to lost[v] once. The unreported sources at v thus lie under pruned
//     shafts charged at v, and their light is at most the sum of those charges, lost[v];
//     each charge was made after checking lost[v] + T(s, v) < pruneFraction x L_v, so
//     lost[v] never exceeds that. A vertex shared by patches of several receiver nodes may
//     be charged by several pruned shafts for one source: counted twice, which only makes
//     the bound conservative. The build is depth first in a fixed child order, so where
//     the budget is spent is still a pure function of the inputs.
//   - Deterministic: every ordering is a strict total order over indices; the layout and
//     every traversal result are a pure function of the inputs (design.md §3).
//
// Cost: traverse() visits shafts depth first, one box–shaft test each (6 slab tests and up
// to 8 planes); it allocates nothing once a TraversalResult has been used once.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "scene/patch_mesh.h"
#include "shadow/light_transport.h"

namespace penumbra::shadow {

inline constexpr uint32_t kNoIndex = 0xFFFFFFFFu;

struct ShaftBuildOptions {
  uint32_t maxReceiversPerLeaf = 8;  // receiver octree leaf size (§6: "at most 8")
  // §6: a shaft below this fraction of L_i (luminance) at every vertex of its receiver
  // node is insignificant (the paper's 2%). 0 keeps every shaft: culling is purely
  // geometric.
  double pruneFraction = 0.02;
  // True: insignificant shafts are pruned only within a budget of pruneFraction of L_i
  // per receiver vertex, the rest kept as coarse leaves (the header's "Bounded loss").
  // False: every insignificant shaft is pruned, as before issue 15, with no bound on the
  // light lost: kept to measure what the budget costs and what it saves.
  bool boundLostLight = true;
};

// One bounding plane of a shaft. Haines' planes join an edge of one box to the parallel
// edge of the other, so each is parallel to the third axis: a * x[axisI] + b * x[axisJ]
// <= d holds inside the shaft.
struct ShaftPlane {
  double a = 0, b = 0, d = 0;
  uint8_t axisI = 0, axisJ = 1;
};

// The shaft between two boxes (Haines & Wallace 1994). At most 8 planes are ever needed:
// a plane joins a face owned by one box alone to a face on another axis owned by the
// other box alone, and 8 is the most such pairs six faces can form.
struct ShaftGeometry {
  scene::Aabb bounds = scene::Aabb::emptyBox();
  std::array<ShaftPlane, 8> planes{};
  uint32_t planeCount = 0;

  // The shaft containing the convex hull of `a` and `b` (both non-empty).
  static ShaftGeometry between(const scene::Aabb& a, const scene::Aabb& b);
  // False only when `box` lies outside the bounds or outside one plane (Haines' reject
  // test); true means "may intersect" (touching counts as intersecting).
  bool mayIntersect(const scene::Aabb& box) const;
};

// Scratch state owned by ShaftHierarchy::traverse(); callers keep it alive between frames
// and do not touch it. Per-source and per-receiver-leaf frame tags make each frame's lists
// duplicate-free without clearing anything (§6.1).
struct TraversalScratch {
  std::vector<uint32_t> sourceTag;    // per source
  std::vector<uint32_t> receiverTag;  // per receiver, by position in receiverOrder()
  std::vector<uint32_t> stack;
  uint32_t lastFrame = 0;
  bool primed = false;
};

struct TraversalResult {
  // Potentially occluded sources (indices into SourceReceiverSets::sources), each once, in
  // the order their first leaf shaft was reached (§6.1 "source list").
  std::vector<uint32_t> sources;
  // Receiver patches (indices into PatchMesh::patches) of the receiver nodes of the leaf
  // shafts hit, each once, node by node (§6.1 "receiver list").
  std::vector<uint32_t> receivers;
  size_t shaftsVisited = 0;  // box–shaft tests performed
  size_t leafShaftsHit = 0;  // leaf shafts the box may intersect
  TraversalScratch scratch;
};

class ShaftHierarchy {
 public:
  using BuildOptions = ShaftBuildOptions;

  // Binary KD-tree node over the source patches. Leaves hold one source.
  struct SourceNode {
    scene::Aabb bounds = scene::Aabb::emptyBox();  // of the node's patches' triangles
    uint32_t parent = kNoIndex;
    std::array<uint32_t, 2> child{kNoIndex, kNoIndex};
    uint32_t source = kNoIndex;  // leaf only: index into SourceReceiverSets::sources
    uint32_t firstLeaf = 0;      // the node's sources are sourceOrder()[firstLeaf, +leafCount)
    uint32_t leafCount = 0;
    // Sum over the node's leaves of RadianceTransfers::sourceAverage, summed children left
    // then right: the "average radiance transfer" that §8 ranks nodes by.
    double averageTransfer = 0;
    bool isLeaf() const { return source != kNoIndex; }
  };

  // Octree node over the receiver patches; children are contiguous.
  struct ReceiverNode {
    scene::Aabb bounds = scene::Aabb::emptyBox();  // of the node's patches' triangles
    uint32_t firstChild = 0;
    uint32_t childCount = 0;  // 0 for a leaf, else 2..8
    uint32_t firstPatch = 0;  // the node's patches are receiverOrder()[firstPatch, +patchCount)
    uint32_t patchCount = 0;
    bool isLeaf() const { return childCount == 0; }
  };

  // A node of the shaft hierarchy; children are contiguous, planes are
  // planes()[firstPlane, +planeCount). A shaft without children is a leaf shaft: its
  // source node (one source) and its receiver node are both leaves, except for a coarse
  // leaf, which reports all the sources and receivers of its nodes.
  struct Shaft {
    scene::Aabb bounds;
    uint32_t sourceNode = 0;
    uint32_t receiverNode = 0;
    uint32_t firstChild = 0;
    uint32_t firstPlane = 0;
    uint8_t childCount = 0;
    uint8_t planeCount = 0;
  };

  // Throws std::invalid_argument when the inputs disagree (transfer arrays of the wrong
  // size, indices out of range, maxReceiversPerLeaf = 0, negative or NaN pruneFraction).
  ShaftHierarchy(const scene::PatchMesh& mesh, const SourceReceiverSets& sets,
                 const RadianceTransfers& transfers, BuildOptions options = {});

  // §6.1: the sources and receivers whose shafts `objectBox` may intersect. `frame` must
  // differ from the previous call's with the same `out` (a repeat is detected and handled
  // by re-initialising the tags, at O(sources + leaves) cost); tags go stale only after
  // 2^32 frames. Allocation-free after the first call with `out`.
  void traverse(const scene::Aabb& objectBox, uint32_t frame, TraversalResult& out) const;

  std::span<const SourceNode> sourceNodes() const { return sourceNodes_; }
  std::span<const ReceiverNode> receiverNodes() const { return receiverNodes_; }
  std::span<const Shaft> shafts() const { return shafts_; }
  std::span<const ShaftPlane> planes() const { return planes_; }
  // Source indices in KD-tree leaf order; receiver patch indices in octree leaf order.
  std::span<const uint32_t> sourceOrder() const { return sourceOrder_; }
  std::span<const uint32_t> receiverOrder() const { return receiverOrder_; }
  // The KD-tree leaf holding source `s`.
  uint32_t sourceLeaf(uint32_t s) const { return sourceLeaf_[s]; }
  size_t sourceCount() const { return sourceLeaf_.size(); }
  // RadianceTransfers::sourceAverage of source `s`.
  double sourceAverage(uint32_t s) const { return sourceNodes_[sourceLeaf_[s]].averageTransfer; }

  size_t shaftCount() const { return shafts_.size(); }
  size_t leafShaftCount() const { return leafShaftCount_; }
  // Leaf shafts above the leaves of either tree (counted in leafShaftCount()): where the
  // hierarchy reports a group of sources or receivers rather than lose their light.
  size_t coarseLeafShaftCount() const { return coarseLeafShaftCount_; }
  // Bytes held by the hierarchy (capacity of every array it keeps).
  size_t memoryBytes() const;

 private:
  struct ShaftTree;   // the hierarchy before it is flattened (shaft_hierarchy.cpp)
  class PruneBudget;  // §6's test with the lost-light budget: a shaft's fate (.cpp)

  // The construction stages, in order; each fills the members named.
  void buildSourceTree(const SourceReceiverSets& sets, const RadianceTransfers& transfers,
                       std::span<const scene::Aabb> patchBox);  // sourceNodes_, Order_, Leaf_
  void buildReceiverTree(const SourceReceiverSets& sets, std::span<const scene::Aabb> patchBox,
                         uint32_t maxReceiversPerLeaf);  // receiverNodes_, receiverOrder_
  ShaftTree buildShaftTree(PruneBudget& pruning);        // coarseLeafShaftCount_
  void flatten(const ShaftTree& tree);  // shafts_, planes_, leafShaftCount_, stackBound_

  std::vector<SourceNode> sourceNodes_;
  std::vector<ReceiverNode> receiverNodes_;
  std::vector<Shaft> shafts_;
  std::vector<ShaftPlane> planes_;
  std::vector<uint32_t> sourceOrder_;
  std::vector<uint32_t> receiverOrder_;
  std::vector<uint32_t> sourceLeaf_;
  size_t leafShaftCount_ = 0;
  size_t coarseLeafShaftCount_ = 0;
  size_t stackBound_ = 0;  // deepest traversal stack, for reserving it once
};

}  // namespace penumbra::shadow
