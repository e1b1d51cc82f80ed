#include "shadow/shaft_hierarchy.h"
#include "core/colour.h"
#include "core/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "shadow/intensity_transfer.h"  // core::splitmix64, a seeded counter-based generator
#include "tests/shaft_test_room.h"

namespace penumbra::shadow {

namespace {

using scene::Aabb;
using testing::buildTestRoom;

// Uniform double in [0, 1) from a counter.
double uniform(uint64_t& counter) {
  return static_cast<double>(core::splitmix64(counter++) >> 11) * 0x1.0p-53;
}

// Segment a-b (inclusive ends) against a closed box: slab clipping.
bool segmentHitsBox(const glm::dvec3& a, const glm::dvec3& b, const Aabb& box) {
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 3; ++k) {
    const double d = b[k] - a[k];
    if (d == 0) {
      if (a[k] < box.min[k] || a[k] > box.max[k]) return false;
      continue;
    }
    double lo = (box.min[k] - a[k]) / d, hi = (box.max[k] - a[k]) / d;
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo);
    t1 = std::min(t1, hi);
    if (t0 > t1) return false;
  }
  return true;
}

// Corners, centre and a few random points of a patch (two triangles).
std::vector<glm::dvec3> patchSamples(const scene::PatchMesh& mesh, uint32_t patch,
                                     uint64_t& counter) {
  const uint32_t* tri = &mesh.indices[3 * mesh.patches[patch].firstTriangle];
  std::vector<glm::dvec3> out;
  for (int k = 0; k < 6; ++k) out.push_back(mesh.positions[tri[k]]);
  out.push_back(mesh.patches[patch].centre);
  for (int k = 0; k < 4; ++k) {
    const uint32_t* t = tri + 3 * (k % 2);
    double u = uniform(counter), v = uniform(counter);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    out.push_back(mesh.positions[t[0]] + u * (mesh.positions[t[1]] - mesh.positions[t[0]]) +
                  v * (mesh.positions[t[2]] - mesh.positions[t[0]]));
  }
  return out;
}

Aabb randomBox(uint64_t& counter) {
  const glm::dvec3 c(4 * uniform(counter), 2.5 * uniform(counter), 4 * uniform(counter));
  const glm::dvec3 half(0.02 + 0.5 * uniform(counter), 0.02 + 0.5 * uniform(counter),
                        0.02 + 0.5 * uniform(counter));
  return Aabb{c - half, c + half};
}

bool hasDuplicates(std::vector<uint32_t> v) {
  std::sort(v.begin(), v.end());
  return std::adjacent_find(v.begin(), v.end()) != v.end();
}

struct ShaftRoom {
  scene::PatchMesh mesh;
  SourceReceiverSets sets;
  RadianceTransfers transfers;
};

ShaftRoom smallRoom() {
  ShaftRoom r;
  buildTestRoom(10, 3, 3, true, r.mesh, r.sets, r.transfers);
  return r;
}

TEST(ShaftGeometry, HainesPlanesHoldTheHullAndCutTheCorners) {
  const Aabb a{{0, 0, 0}, {1, 1, 1}};
  const Aabb b{{5, 5, 5}, {6, 6, 6}};
  const ShaftGeometry g = ShaftGeometry::between(a, b);
  // Each box owns the three faces on its side: every cross-axis pair needs a plane.
  EXPECT_EQ(g.planeCount, 6u);
  uint64_t counter = 1;
  for (int k = 0; k < 2000; ++k) {
    const glm::dvec3 pa = a.min + glm::dvec3(uniform(counter), uniform(counter), uniform(counter));
    const glm::dvec3 pb = b.min + glm::dvec3(uniform(counter), uniform(counter), uniform(counter));
    const glm::dvec3 p = pa + uniform(counter) * (pb - pa);
    EXPECT_TRUE(g.mayIntersect(Aabb{p, p})) << p.x << " " << p.y << " " << p.z;
  }
  // Inside the joint bounding box but off the diagonal: only the planes reject these.
  EXPECT_FALSE(g.mayIntersect(Aabb{{5, 0, 0}, {5.5, 0.5, 0.5}}));
  EXPECT_FALSE(g.mayIntersect(Aabb{{0, 5, 5}, {0.5, 6, 6}}));
  EXPECT_TRUE(g.mayIntersect(Aabb{{2.5, 2.5, 2.5}, {3.5, 3.5, 3.5}}));
  EXPECT_FALSE(g.mayIntersect(Aabb{{7, 0, 0}, {8, 1, 1}}));

  // A box nested in the other's extent on one axis and owning both faces there gives
  // planes between its two x faces and the other's y faces only.
  const Aabb wide{{0, 0, 0}, {10, 1, 1}};
  const Aabb tall{{4, 3, 0}, {5, 4, 1}};
  const ShaftGeometry h = ShaftGeometry::between(wide, tall);
  EXPECT_EQ(h.planeCount, 2u);  // z faces are shared, y faces' corners join x faces
  EXPECT_FALSE(h.mayIntersect(Aabb{{0, 3, 0}, {1, 4, 1}}));
  EXPECT_TRUE(h.mayIntersect(Aabb{{4.4, 2, 0.5}, {4.6, 2.1, 0.6}}));
  // Identical boxes: the shaft is the box itself.
  EXPECT_EQ(ShaftGeometry::between(a, a).planeCount, 0u);
}

TEST(ShaftHierarchy, TreesCoverTheSetsOnce) {
  const ShaftRoom room = smallRoom();
  const ShaftHierarchy h(room.mesh, room.sets, room.transfers, {8, 0.0});
  // KD-tree: one leaf per source, parents consistent, averages add up.
  ASSERT_EQ(h.sourceCount(), room.sets.sources.size());
  double total = 0;
  for (uint32_t s = 0; s < h.sourceCount(); ++s) {
    const auto& leaf = h.sourceNodes()[h.sourceLeaf(s)];
    EXPECT_TRUE(leaf.isLeaf());
    EXPECT_EQ(leaf.source, s);
    EXPECT_EQ(h.sourceOrder()[leaf.firstLeaf], s);
    total += room.transfers.sourceAverage[s];
  }
  EXPECT_NEAR(h.sourceNodes()[0].averageTransfer, total, 1e-9 * total);
  EXPECT_EQ(h.sourceNodes().size(), 2 * h.sourceCount() - 1);
  for (uint32_t n = 1; n < h.sourceNodes().size(); ++n) {
    const auto& parent = h.sourceNodes()[h.sourceNodes()[n].parent];
    EXPECT_TRUE(parent.child[0] == n || parent.child[1] == n);
  }
  // Octree: every receiver once, leaves of at most 8, children inside their parent.
  std::vector<uint32_t> order(h.receiverOrder().begin(), h.receiverOrder().end());
  std::sort(order.begin(), order.end());
  EXPECT_EQ(order, room.sets.receivers);
  for (const auto& node : h.receiverNodes()) {
    if (node.isLeaf()) {
      EXPECT_LE(node.patchCount, 8u);
      continue;
    }
    uint32_t covered = 0;
    for (uint32_t c = node.firstChild; c < node.firstChild + node.childCount; ++c) {
      const auto& child = h.receiverNodes()[c];
      EXPECT_EQ(child.firstPatch, node.firstPatch + covered);
      covered += child.patchCount;
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(child.bounds.min, node.bounds.min)));
      EXPECT_TRUE(glm::all(glm::lessThanEqual(child.bounds.max, node.bounds.max)));
    }
    EXPECT_EQ(covered, node.patchCount);
  }
  // Unpruned, every (source, receiver leaf) pair ends in exactly one leaf shaft.
  size_t receiverLeaves = 0;
  for (const auto& node : h.receiverNodes()) receiverLeaves += node.isLeaf();
  EXPECT_EQ(h.leafShaftCount(), h.sourceCount() * receiverLeaves);
  EXPECT_EQ(h.deadEndShaftCount(), 0u);
}

// The central promise of §6.1: whenever a segment from a source patch to a receiver patch
// passes through the object box, both are reported. With pruneFraction = 0 for every
// pair; with the paper's 2% for every pair that carries >= 2% of L_i at one of the
// receiver's own vertices.
void checkConservative(double pruneFraction, int boxes) {
  const ShaftRoom room = smallRoom();
  const ShaftHierarchy h(room.mesh, room.sets, room.transfers, {8, pruneFraction});
  uint64_t counter = 99;
  std::vector<std::vector<glm::dvec3>> samples(room.mesh.patches.size());
  for (uint32_t p : room.sets.sources) samples[p] = patchSamples(room.mesh, p, counter);
  for (uint32_t p : room.sets.receivers) samples[p] = patchSamples(room.mesh, p, counter);
  // Significant (source, receiver patch) pairs under the 2% rule.
  std::vector<std::vector<char>> significant(room.sets.sources.size(),
                                             std::vector<char>(room.mesh.patches.size(), 0));
  for (uint32_t s = 0; s < room.sets.sources.size(); ++s) {
    for (uint32_t e = room.transfers.sourceStart[s]; e < room.transfers.sourceStart[s + 1]; ++e) {
      const uint32_t i = room.transfers.entryVertex[e];
      if (core::luminance(room.transfers.entryTransfer[e]) <
          pruneFraction * core::luminance(room.transfers.vertexRadiance[i])) {
        continue;
      }
      const uint32_t v = room.transfers.receiverVertices[i];
      for (uint32_t p : room.sets.receivers) {
        const uint32_t* tri = &room.mesh.indices[3 * room.mesh.patches[p].firstTriangle];
        if (std::find(tri, tri + 6, v) != tri + 6) significant[s][p] = 1;
      }
    }
  }
  TraversalResult out;
  size_t hits = 0, reportedSources = 0;
  for (int k = 0; k < boxes; ++k) {
    const Aabb box = randomBox(counter);
    h.traverse(box, static_cast<uint32_t>(k), out);
    std::vector<char> source(room.sets.sources.size(), 0), receiver(room.mesh.patches.size(), 0);
    for (uint32_t s : out.sources) source[s] = 1;
    for (uint32_t r : out.receivers) receiver[r] = 1;
    reportedSources += out.sources.size();
    for (uint32_t s = 0; s < room.sets.sources.size(); ++s) {
      for (uint32_t r : room.sets.receivers) {
        if (pruneFraction > 0 && !significant[s][r]) continue;
        bool hit = false;
        for (const auto& a : samples[room.sets.sources[s]]) {
          for (const auto& b : samples[r]) hit = hit || segmentHitsBox(a, b, box);
        }
        if (!hit) continue;
        ++hits;
        ASSERT_TRUE(source[s]) << "box " << k << " missed source " << s;
        ASSERT_TRUE(receiver[r]) << "box " << k << " missed receiver " << r;
      }
    }
  }
  EXPECT_GT(hits, 1000u);  // the boxes did cut many shafts
  // ...and culling did something: far from every box hitting every source.
  EXPECT_LT(reportedSources, static_cast<size_t>(boxes) * room.sets.sources.size());
}

TEST(ShaftHierarchy, ConservativeUnpruned) {
  checkConservative(0.0, 150);
}
TEST(ShaftHierarchy, ConservativeForSignificantPairsWhenPruned) {
  checkConservative(0.02, 150);
}

TEST(ShaftHierarchy, FrameTagsNeverDuplicateAndNeverLeak) {
  const ShaftRoom room = smallRoom();
  const ShaftHierarchy h(room.mesh, room.sets, room.transfers, {8, 0.0});
  TraversalResult reused;
  uint64_t counter = 5;
  const Aabb first = randomBox(counter);
  h.traverse(first, 0, reused);  // frame 0 first: tags must not start "current"
  const auto* sourcesData = reused.sources.data();
  const auto* receiversData = reused.receivers.data();
  for (uint32_t frame = 1; frame < 400; ++frame) {
    const Aabb box = randomBox(counter);
    // Every 50th frame repeats the previous number (the caller's mistake): still exact.
    const uint32_t tag = frame % 50 == 0 ? frame - 1 : frame;
    h.traverse(box, tag, reused);
    TraversalResult fresh;
    h.traverse(box, 12345, fresh);
    EXPECT_FALSE(hasDuplicates(reused.sources));
    EXPECT_FALSE(hasDuplicates(reused.receivers));
    EXPECT_EQ(reused.sources, fresh.sources);
    EXPECT_EQ(reused.receivers, fresh.receivers);
    EXPECT_EQ(reused.shaftsVisited, fresh.shaftsVisited);
  }
  // Allocation-free after warm-up: the lists never moved.
  EXPECT_EQ(reused.sources.data(), sourcesData);
  EXPECT_EQ(reused.receivers.data(), receiversData);
}

TEST(ShaftHierarchy, FarOrEmptyBoxFindsNothing) {
  const ShaftRoom room = smallRoom();
  const ShaftHierarchy h(room.mesh, room.sets, room.transfers);
  TraversalResult out;
  h.traverse(Aabb{{100, 100, 100}, {101, 101, 101}}, 1, out);
  EXPECT_TRUE(out.sources.empty());
  EXPECT_TRUE(out.receivers.empty());
  EXPECT_EQ(out.shaftsVisited, 1u);  // rejected at the root
  h.traverse(Aabb::emptyBox(), 2, out);
  EXPECT_TRUE(out.sources.empty());
  // A box filling the room meets every kept leaf shaft.
  h.traverse(Aabb{{-1, -1, -1}, {5, 5, 5}}, 3, out);
  EXPECT_EQ(out.leafShaftsHit, h.leafShaftCount());
}

TEST(ShaftHierarchy, PruningDropsShaftsAndIsDeterministic) {
  const ShaftRoom room = smallRoom();
  const ShaftHierarchy all(room.mesh, room.sets, room.transfers, {8, 0.0});
  const ShaftHierarchy pruned(room.mesh, room.sets, room.transfers, {8, 0.02});
  const ShaftHierarchy again(room.mesh, room.sets, room.transfers, {8, 0.02});
  EXPECT_LT(pruned.shaftCount(), all.shaftCount());
  EXPECT_LT(pruned.memoryBytes(), all.memoryBytes());
  ASSERT_EQ(pruned.shaftCount(), again.shaftCount());
  for (size_t k = 0; k < pruned.shaftCount(); ++k) {
    EXPECT_EQ(pruned.shafts()[k].sourceNode, again.shafts()[k].sourceNode);
    EXPECT_EQ(pruned.shafts()[k].receiverNode, again.shafts()[k].receiverNode);
  }
  // Everything pruned: no shafts, and traversal still works.
  const ShaftHierarchy none(room.mesh, room.sets, room.transfers, {8, 1e9});
  EXPECT_EQ(none.shaftCount(), 0u);
  TraversalResult out;
  none.traverse(Aabb{{0, 0, 0}, {4, 2.5, 4}}, 1, out);
  EXPECT_TRUE(out.sources.empty());
}

TEST(ShaftHierarchy, RejectsInconsistentInput) {
  ShaftRoom room = smallRoom();
  RadianceTransfers bad = room.transfers;
  bad.sourceAverage.pop_back();
  EXPECT_THROW(ShaftHierarchy(room.mesh, room.sets, bad), std::invalid_argument);
  EXPECT_THROW(ShaftHierarchy(room.mesh, room.sets, room.transfers, {0, 0.02}),
               std::invalid_argument);
  SourceReceiverSets sets = room.sets;
  sets.receivers.push_back(static_cast<uint32_t>(room.mesh.patches.size()));
  EXPECT_THROW(ShaftHierarchy(room.mesh, sets, room.transfers), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
