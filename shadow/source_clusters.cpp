#include "shadow/source_clusters.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra::shadow {

void selectSourceClusters(const ShaftHierarchy& hierarchy,
                          std::span<const uint32_t> occludedSources, uint32_t frame, size_t n,
                          ClusterSelection& out, const scene::Aabb* occluder) {
  out.clusters.clear();
  out.sources.clear();
  const std::span<const ShaftHierarchy::SourceNode> nodes = hierarchy.sourceNodes();
  ClusterScratch& sc = out.scratch;
  // Same tag discipline as the traversal: start one frame behind, reset on a repeat.
  if (sc.nodeTag.size() != nodes.size() || !sc.primed || sc.lastFrame == frame) {
    sc.nodeTag.assign(nodes.size(), frame - 1);
    sc.nodeKey.assign(nodes.size(), 0.0);
    sc.open.reserve(nodes.size());
    sc.done.reserve(nodes.size());
    sc.stack.reserve(nodes.size());
    out.clusters.reserve(hierarchy.sourceCount());
    out.sources.reserve(hierarchy.sourceCount());
    sc.primed = true;
  }
  sc.lastFrame = frame;
  for (uint32_t s : occludedSources) {
    if (s >= hierarchy.sourceCount()) {
      throw std::out_of_range("selectSourceClusters: source index out of range");
    }
  }
  if (occludedSources.empty() || n == 0) return;

  // Fig. 5b: mark the occluded branches. A walk stops at the first node already marked
  // this frame, so the marking costs one visit per marked node.
  for (uint32_t s : occludedSources) {
    for (uint32_t node = hierarchy.sourceLeaf(s); node != kNoIndex && sc.nodeTag[node] != frame;
         node = nodes[node].parent) {
      sc.nodeTag[node] = frame;
    }
  }

  // Fig. 6: the list is `open` (marked inner nodes, a max-heap on the node's key, lower
  // node index first on ties) plus `done` (marked leaves, final).
  // The key a listed node is split by: §8's average transfer, or, with the occluder's
  // bounds, that times the node's extent over its distance from the occluder. Why: one
  // shadow map from a point stands in for sources spread over a node of diameter w at
  // distance d from the occluder; on a receiver h behind the occluder the true penumbra
  // is about w·h/d wide, so the light the point puts on the wrong side of the edge grows
  // with E·w/d (h is the same for every node). Splitting the node where that product is
  // largest removes the most misplaced light: a bright but compact panel far away is left
  // whole before a dimmer window close to the product that spans a metre.
  const auto key = [&](uint32_t node) {
    if (occluder == nullptr) return nodes[node].averageTransfer;
    const double extent = glm::length(nodes[node].bounds.size());
    // 1 mm: a source inside the occluder's box has no meaningful direction; any positive
    // floor keeps the key finite and the order deterministic.
    const double distance =
        std::max(glm::length(nodes[node].bounds.centre() - occluder->centre()), 1e-3);
    return nodes[node].averageTransfer * (extent / distance);
  };
  // Each listed node's key is computed once, when it is listed (two square roots per heap
  // comparison otherwise).
  const auto lessUrgent = [&](uint32_t a, uint32_t b) {
    const double ka = sc.nodeKey[a], kb = sc.nodeKey[b];
    return ka != kb ? ka < kb : a > b;
  };
  sc.open.clear();
  sc.done.clear();
  // A node with a single marked child stands for the same occluded sources as that child,
  // so a listed node is first narrowed down to the top of its marked subtree's first fork
  // (or its only marked leaf): the cluster is then the tightest node over its sources.
  const auto add = [&](uint32_t node) {
    while (!nodes[node].isLeaf()) {
      const auto [left, right] = nodes[node].child;
      const bool l = sc.nodeTag[left] == frame, r = sc.nodeTag[right] == frame;
      if (l && r) break;
      node = l ? left : right;
    }
    if (nodes[node].isLeaf()) {
      sc.done.push_back(node);
    } else {
      sc.nodeKey[node] = key(node);
      sc.open.push_back(node);
      std::push_heap(sc.open.begin(), sc.open.end(), lessUrgent);
    }
  };
  add(0);
  // Every listed inner node forks, so each expansion adds exactly one node: the loop ends
  // with min(n, occluded sources) nodes.
  while (sc.open.size() + sc.done.size() < n && !sc.open.empty()) {
    std::pop_heap(sc.open.begin(), sc.open.end(), lessUrgent);
    const uint32_t node = sc.open.back();
    sc.open.pop_back();
    for (uint32_t child : nodes[node].child) {
      if (sc.nodeTag[child] == frame) add(child);
    }
  }

  // Each listed node's occluded leaves, found by walking its marked subtree.
  const auto emit = [&](uint32_t node) {
    SourceCluster cluster;
    cluster.node = node;
    cluster.nodeTransfer = nodes[node].averageTransfer;
    cluster.firstSource = static_cast<uint32_t>(out.sources.size());
    sc.stack.clear();
    sc.stack.push_back(node);
    while (!sc.stack.empty()) {
      const ShaftHierarchy::SourceNode& at = nodes[sc.stack.back()];
      sc.stack.pop_back();
      if (at.isLeaf()) {
        out.sources.push_back(at.source);
        continue;
      }
      for (uint32_t child : at.child) {
        if (sc.nodeTag[child] == frame) sc.stack.push_back(child);
      }
    }
    const auto first = out.sources.begin() + cluster.firstSource;
    std::sort(first, out.sources.end(), [&](uint32_t a, uint32_t b) {
      const double ka = hierarchy.sourceAverage(a), kb = hierarchy.sourceAverage(b);
      return ka != kb ? ka > kb : a < b;
    });
    cluster.sourceCount = static_cast<uint32_t>(out.sources.end() - first);
    cluster.representative = *first;
    // Summed in the sorted order, so the value does not depend on the input order.
    for (auto it = first; it != out.sources.end(); ++it) {
      cluster.occludedTransfer += hierarchy.sourceAverage(*it);
    }
    out.clusters.push_back(cluster);
  };
  for (uint32_t node : sc.done) emit(node);
  for (uint32_t node : sc.open) emit(node);
  // Ties go to the lower representative index, so with one source per cluster the order
  // is exactly the per-patch §7.1.1 order (representatives are distinct: clusters are
  // disjoint).
  std::sort(
      out.clusters.begin(), out.clusters.end(), [](const SourceCluster& a, const SourceCluster& b) {
        return a.occludedTransfer != b.occludedTransfer ? a.occludedTransfer > b.occludedTransfer
                                                        : a.representative < b.representative;
      });
}

}  // namespace penumbra::shadow
