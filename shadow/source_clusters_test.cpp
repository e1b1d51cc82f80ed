#include "shadow/source_clusters.h"
#include "core/colour.h"
#include "core/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "shadow/intensity_transfer.h"  // core::splitmix64
#include "tests/shaft_test_room.h"

namespace penumbra::shadow {
namespace {

using scene::Aabb;

struct Fixture {
  scene::PatchMesh mesh;
  SourceReceiverSets sets;
  RadianceTransfers transfers;
  ShaftHierarchy build(double pruneFraction) const {
    return ShaftHierarchy(mesh, sets, transfers, {8, pruneFraction});
  }
};

// 1,024 floor receivers and 60 ceiling sources: the size the brief times.
Fixture showroom() {
  Fixture f;
  testing::buildTestRoom(32, 10, 6, false, f.mesh, f.sets, f.transfers);
  return f;
}

std::vector<uint32_t> sorted(std::vector<uint32_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// A pseudo-random subset of the sources, in a scrambled order.
std::vector<uint32_t> randomSubset(size_t count, uint64_t seed, double keep) {
  std::vector<uint32_t> out;
  for (uint32_t s = 0; s < count; ++s) {
    if (static_cast<double>(core::splitmix64(seed * 1000003u + s) >> 11) * 0x1.0p-53 < keep) {
      out.push_back(s);
    }
  }
  std::reverse(out.begin(), out.end());
  return out;
}

bool isAncestor(const ShaftHierarchy& h, uint32_t node, uint32_t leaf) {
  for (uint32_t n = leaf; n != kNoIndex; n = h.sourceNodes()[n].parent) {
    if (n == node) return true;
  }
  return false;
}

// How much of the light the kept leaf shafts can report: transfer luminance of the
// (source, vertex) entries that some leaf shaft covers, over all entries.
double coveredLight(const Fixture& f, const ShaftHierarchy& h) {
  std::vector<std::vector<char>> covered(h.sourceCount(),
                                         std::vector<char>(f.mesh.positions.size(), 0));
  for (const auto& shaft : h.shafts()) {
    if (shaft.childCount != 0) continue;
    const auto& sn = h.sourceNodes()[shaft.sourceNode];
    const auto& rn = h.receiverNodes()[shaft.receiverNode];
    for (uint32_t j = sn.firstLeaf; j < sn.firstLeaf + sn.leafCount; ++j) {
      for (uint32_t k = rn.firstPatch; k < rn.firstPatch + rn.patchCount; ++k) {
        const auto& patch = f.mesh.patches[h.receiverOrder()[k]];
        const uint32_t* tri = &f.mesh.indices[3 * patch.firstTriangle];
        for (int v = 0; v < 6; ++v) covered[h.sourceOrder()[j]][tri[v]] = 1;
      }
    }
  }
  double kept = 0, total = 0;
  for (uint32_t s = 0; s < h.sourceCount(); ++s) {
    for (uint32_t e = f.transfers.sourceStart[s]; e < f.transfers.sourceStart[s + 1]; ++e) {
      const double l = core::luminance(f.transfers.entryTransfer[e]);
      total += l;
      if (covered[s][f.transfers.receiverVertices[f.transfers.entryVertex[e]]]) kept += l;
    }
  }
  return kept / total;
}

TEST(SourceClusters, ConserveTheOccludedSetForEveryN) {
  const Fixture f = showroom();
  const ShaftHierarchy h = f.build(0.02);
  ClusterSelection sel;
  uint32_t frame = 1;
  for (uint64_t trial = 0; trial < 6; ++trial) {
    const std::vector<uint32_t> occluded =
        randomSubset(h.sourceCount(), trial, 0.2 + 0.15 * static_cast<double>(trial));
    ASSERT_FALSE(occluded.empty());
    for (size_t n = 1; n <= occluded.size() + 2; ++n) {
      selectSourceClusters(h, occluded, frame++, n, sel);
      ASSERT_EQ(sel.clusters.size(), std::min(n, occluded.size()));
      // Multiset equality: every occluded source in exactly one cluster.
      EXPECT_EQ(sorted(sel.sources), sorted(occluded)) << "n = " << n;
      uint32_t listed = 0;
      for (size_t k = 0; k < sel.clusters.size(); ++k) {
        const SourceCluster& c = sel.clusters[k];
        listed += c.sourceCount;
        ASSERT_GT(c.sourceCount, 0u);
        EXPECT_EQ(c.representative, sel.sources[c.firstSource]);
        double sum = 0;
        for (uint32_t i = c.firstSource; i < c.firstSource + c.sourceCount; ++i) {
          const uint32_t s = sel.sources[i];
          EXPECT_TRUE(isAncestor(h, c.node, h.sourceLeaf(s)));
          // The representative carries the most energy in its cluster.
          EXPECT_GE(h.sourceAverage(c.representative), h.sourceAverage(s));
          sum += h.sourceAverage(s);
        }
        EXPECT_NEAR(c.occludedTransfer, sum, 1e-12 * sum);
        EXPECT_LE(c.occludedTransfer, c.nodeTransfer * (1 + 1e-12));
        if (k > 0) {
          EXPECT_GE(sel.clusters[k - 1].occludedTransfer, c.occludedTransfer);
        }
      }
      EXPECT_EQ(listed, sel.sources.size());
    }
  }
}

TEST(SourceClusters, EnoughPassesGiveThePerPatchList) {
  const Fixture f = showroom();
  const ShaftHierarchy h = f.build(0.02);
  const std::vector<uint32_t> occluded = randomSubset(h.sourceCount(), 11, 0.5);
  ClusterSelection sel;
  selectSourceClusters(h, occluded, 1, occluded.size(), sel);
  // §7.1.1 order: decreasing average transfer, lower index first on ties.
  std::vector<uint32_t> expected = occluded;
  std::sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) {
    return h.sourceAverage(a) != h.sourceAverage(b) ? h.sourceAverage(a) > h.sourceAverage(b)
                                                    : a < b;
  });
  ASSERT_EQ(sel.clusters.size(), occluded.size());
  for (size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(sel.clusters[k].sourceCount, 1u);
    EXPECT_EQ(sel.clusters[k].representative, expected[k]);
    EXPECT_EQ(sel.clusters[k].node, h.sourceLeaf(expected[k]));
  }
}

TEST(SourceClusters, Figure6ExpandsTheBrightestMarkedNodeFirst) {
  const Fixture f = showroom();
  const ShaftHierarchy h = f.build(0.02);
  std::vector<uint32_t> all(h.sourceCount());
  for (uint32_t s = 0; s < all.size(); ++s) all[s] = s;
  ClusterSelection sel;
  selectSourceClusters(h, all, 1, 1, sel);
  ASSERT_EQ(sel.clusters.size(), 1u);
  EXPECT_EQ(sel.clusters[0].node, 0u);  // one pass: the root stands for everything
  selectSourceClusters(h, all, 2, 2, sel);
  const auto& root = h.sourceNodes()[0];
  ASSERT_EQ(sel.clusters.size(), 2u);
  EXPECT_EQ(sorted({sel.clusters[0].node, sel.clusters[1].node}),
            sorted({root.child[0], root.child[1]}));
  // Third pass: the root child with the larger average transfer is the one split.
  selectSourceClusters(h, all, 3, 3, sel);
  const uint32_t brighter = h.sourceNodes()[root.child[0]].averageTransfer >=
                                    h.sourceNodes()[root.child[1]].averageTransfer
                                ? root.child[0]
                                : root.child[1];
  const uint32_t dimmer = brighter == root.child[0] ? root.child[1] : root.child[0];
  std::vector<uint32_t> nodes;
  for (const auto& c : sel.clusters) nodes.push_back(c.node);
  EXPECT_NE(std::find(nodes.begin(), nodes.end(), dimmer), nodes.end());
  EXPECT_EQ(std::find(nodes.begin(), nodes.end(), brighter), nodes.end());
  // Only marked branches are entered: a single occluded source is one leaf cluster.
  selectSourceClusters(h, std::vector<uint32_t>{7}, 4, 5, sel);
  ASSERT_EQ(sel.clusters.size(), 1u);
  EXPECT_EQ(sel.clusters[0].node, h.sourceLeaf(7));
}

// With the occluder's bounds the node split first is the one whose transfer times angular
// size from the occluder is largest, and the clusters still partition the occluded set.
TEST(SourceClusters, WithAnOccluderTheLightSpreadWidestAroundItIsSplitFirst) {
  const Fixture f = showroom();
  const ShaftHierarchy h = f.build(0.02);
  std::vector<uint32_t> all(h.sourceCount());
  for (uint32_t s = 0; s < all.size(); ++s) all[s] = s;
  const auto& nodes = h.sourceNodes();
  const auto& root = nodes[0];
  const auto key = [&](uint32_t node, const Aabb& box) {
    return nodes[node].averageTransfer * glm::length(nodes[node].bounds.size()) /
           glm::length(nodes[node].bounds.centre() - box.centre());
  };
  // Boxes under either root child's sources, low in the room: near one child, the other's
  // key falls by its larger distance, so which child is split follows the box.
  int splitLeft = 0, splitRight = 0;
  for (uint32_t side = 0; side < 2; ++side) {
    const glm::dvec3 c = nodes[root.child[side]].bounds.centre();
    const Aabb box{glm::dvec3(c.x - 0.2, 0.0, c.z - 0.2), glm::dvec3(c.x + 0.2, 0.4, c.z + 0.2)};
    ClusterSelection sel;
    selectSourceClusters(h, all, 1, 3, sel, &box);
    ASSERT_EQ(sel.clusters.size(), 3u);
    const uint32_t expectedSplit =
        key(root.child[0], box) >= key(root.child[1], box) ? root.child[0] : root.child[1];
    const uint32_t kept = expectedSplit == root.child[0] ? root.child[1] : root.child[0];
    std::vector<uint32_t> listed;
    for (const auto& cl : sel.clusters) listed.push_back(cl.node);
    EXPECT_NE(std::find(listed.begin(), listed.end(), kept), listed.end()) << "side " << side;
    EXPECT_EQ(std::find(listed.begin(), listed.end(), expectedSplit), listed.end());
    (expectedSplit == root.child[0] ? splitLeft : splitRight) += 1;
    for (size_t n = 1; n <= all.size(); n += 7) {
      selectSourceClusters(h, all, static_cast<uint32_t>(10 + n + 100 * side), n, sel, &box);
      ASSERT_EQ(sel.clusters.size(), n);
      EXPECT_EQ(sorted(sel.sources), all) << "n = " << n;
    }
  }
  // The test room is symmetric enough that the box decides: each side was split once.
  EXPECT_EQ(splitLeft, 1);
  EXPECT_EQ(splitRight, 1);
}

TEST(SourceClusters, DeterministicWhateverTheInputOrder) {
  const Fixture f = showroom();
  const ShaftHierarchy h = f.build(0.02);
  std::vector<uint32_t> occluded = randomSubset(h.sourceCount(), 3, 0.6);
  std::vector<uint32_t> shuffled = occluded;
  std::reverse(shuffled.begin(), shuffled.end());
  std::rotate(shuffled.begin(), shuffled.begin() + 3, shuffled.end());
  shuffled.push_back(shuffled.front());  // a repeated index counts once
  ClusterSelection a, b;
  for (size_t n = 1; n <= 12; ++n) {
    selectSourceClusters(h, occluded, static_cast<uint32_t>(n), n, a);
    selectSourceClusters(h, shuffled, static_cast<uint32_t>(100 + n), n, b);
    EXPECT_EQ(a.sources, b.sources);
    ASSERT_EQ(a.clusters.size(), b.clusters.size());
    for (size_t k = 0; k < a.clusters.size(); ++k) {
      EXPECT_EQ(a.clusters[k].node, b.clusters[k].node);
      EXPECT_EQ(a.clusters[k].firstSource, b.clusters[k].firstSource);
      EXPECT_EQ(a.clusters[k].occludedTransfer, b.clusters[k].occludedTransfer);  // bitwise
    }
  }
  selectSourceClusters(h, std::vector<uint32_t>{}, 50, 4, a);
  EXPECT_TRUE(a.clusters.empty());
  EXPECT_TRUE(a.sources.empty());
  selectSourceClusters(h, occluded, 51, 0, a);
  EXPECT_TRUE(a.clusters.empty());
  EXPECT_THROW(selectSourceClusters(h, std::vector<uint32_t>{9999}, 52, 4, a), std::out_of_range);
}

// Traversal + selection per frame, as the kiosk runs them (timed in bench/shadow_bench.cpp):
// after the first frame the selection reuses its storage, and pruning only ever removes
// sources (the unpruned hierarchy is the geometric floor of the source list). Coarse
// leaves keep light that dropping them would lose.
TEST(SourceClusters, SlidingObjectReusesStorageAndPruningOnlyRemovesSources) {
  const Fixture f = showroom();
  const ShaftHierarchy h = f.build(0.02);
  const ShaftHierarchy unpruned = f.build(0.0);
  TraversalResult traversal, everything;
  ClusterSelection sel;
  // A 0.5 m object sliding across the floor, one position per frame.
  const auto boxAt = [](int k) {
    const double x = 0.5 + 3.0 * (k % 200) / 200.0;
    return Aabb{{x, 0.0, 1.5}, {x + 0.5, 0.5, 2.0}};
  };
  h.traverse(boxAt(0), 0, traversal);
  selectSourceClusters(h, traversal.sources, 0, 16, sel);
  const auto* clusterData = sel.clusters.data();
  size_t sources = 0;
  for (int k = 1; k <= 200; ++k) {
    h.traverse(boxAt(k), static_cast<uint32_t>(k), traversal);
    selectSourceClusters(h, traversal.sources, static_cast<uint32_t>(k), 16, sel);
    unpruned.traverse(boxAt(k), static_cast<uint32_t>(k), everything);
    sources += traversal.sources.size();
    EXPECT_GE(everything.sources.size(), traversal.sources.size()) << "frame " << k;
  }
  EXPECT_EQ(sel.clusters.data(), clusterData);  // no reallocation after warm-up
  EXPECT_GT(sources, 0u);

  // Unbudgeted pruning (boundLostLight = false) loses light the budget keeps.
  const ShaftHierarchy dropped(f.mesh, f.sets, f.transfers, {8, 0.02, false});
  EXPECT_LT(dropped.shaftCount(), h.shaftCount());
  EXPECT_GE(coveredLight(f, h), coveredLight(f, dropped));
}

}  // namespace
}  // namespace penumbra::shadow
