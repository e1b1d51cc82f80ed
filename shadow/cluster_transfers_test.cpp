// The frame's transfers: receiver vertices gathered once each from the receiver patches,
// each cluster's transfer the sum of its sources' L_ij, S by Fig. 4 (or at the measured
// shares once the feedback has some), the same for the product's vertices, and the probes.
#include "shadow/cluster_transfers.h"

#include <gtest/gtest.h>

#include "shadow/intensity_transfer.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {
namespace {

// Two receiver patches on a strip of six vertices; vertex 5 is no receiver vertex. Three
// sources in two clusters: k0 = {0, 2}, k1 = {1}.
struct Strip {
  Strip() {
    const std::vector<glm::dvec3> p{{0, 0, 0}, {1, 0, 0}, {1, 0, 1},
                                    {0, 0, 1}, {2, 0, 0}, {2, 0, 1}};
    mesh.positions = p;
    mesh.indices = {0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2};
    mesh.patches.resize(2);
    mesh.patches[1].firstTriangle = 2;
    for (const glm::dvec3& v : p) bundle.view.staticMesh.positions.push_back(scene::toVec3(v));
    bundle.tone = ToneCurve::gamma(1.0);
    bundle.sets.sources = {7, 8, 9};  // patch ids: Fig. 4's set of each cluster's light
    RadianceTransfers& t = bundle.transfers;
    t.receiverVertices = {0, 1, 2, 3, 4};
    t.vertexRadiance = {{2, 2, 2}, {3, 3, 3}, {4, 4, 4}, {2, 1, 2}, {5, 5, 5}};
    // Source 0 -> vertices 0, 1, 2, 4; source 1 -> 1, 3; source 2 -> 2.
    t.sourceStart = {0, 4, 6, 7};
    t.entryVertex = {0, 1, 2, 4, 1, 3, 2};
    t.entryTransfer = {{0.5f, 0.5f, 0.5f}, {1, 1, 1}, {0.25f, 0.5f, 1}, {2, 2, 2},
                       {1, 0.5f, 0.5f},    {1, 1, 1}, {1.5f, 1, 0.5f}};
    selection.clusters = {SourceCluster{0, 0, 0, 2, 0, 0}, SourceCluster{1, 1, 2, 1, 0, 0}};
    selection.sources = {0, 2, 1};
    productPositions = {{0.5f, 1, 0.5f}, {0.5f, 2, 0.5f}};
    productRadiance = {{1, 1, 1}, {2, 2, 2}};
    productSourceTransfers = {{0.25, 0.25, 0.25}, {0.5, 0.5, 0.5},  // source 0
                              {0.125, 0, 0},      {0, 0.25, 0},     // source 1
                              {0.25, 0, 0.25},    {0, 0, 0.5}};     // source 2
  }
  ProductLight product() const {
    return {productPositions, productRadiance, productSourceTransfers};
  }

  SceneBundle bundle;
  scene::PatchMesh mesh;
  ClusterSelection selection;
  std::vector<core::Vec3> productPositions;
  std::vector<glm::dvec3> productRadiance, productSourceTransfers;
};

glm::dvec3 entry(const Strip& s, size_t e) {
  return glm::dvec3(s.bundle.transfers.entryTransfer[e]);
}

TEST(ClusterTransfers, SumsEachClustersSourcesAtEachVertex) {
  const Strip s;
  ClusterTransfers transfers(s.bundle, s.mesh, {1, true, true, TransferKind::kFineLevels});
  OcclusionFeedback feedback(5, 3, true);
  feedback.productPlaced(2);
  const std::vector<uint32_t> receivers{1, 0};
  transfers.compute(receivers, s.selection, 1, s.product(), feedback);

  // Patch 1's triangles first (1, 4, 5; 1, 5, 2), then patch 0's new vertices.
  EXPECT_EQ(
      std::vector<uint32_t>(transfers.frameVertices().begin(), transfers.frameVertices().end()),
      (std::vector<uint32_t>{1, 4, 2, 0, 3}));
  ASSERT_EQ(transfers.clusters(), 2u);
  const std::span<const glm::dvec3> t = transfers.receiverTransfers();
  const glm::dvec3 zero(0.0);
  const std::vector<glm::dvec3> expected{entry(s, 1),
                                         entry(s, 4),  // vertex 1: k0 = source 0, k1 = source 1
                                         entry(s, 3),
                                         zero,  // vertex 4
                                         zero + entry(s, 2) + entry(s, 6),
                                         zero,  // vertex 2: sources 0 then 2
                                         entry(s, 0),
                                         zero,  // vertex 0
                                         zero,
                                         entry(s, 5)};  // vertex 3
  EXPECT_EQ(std::vector<glm::dvec3>(t.begin(), t.end()), expected);

  // S: Fig. 4 with each cluster in its representative patch's set.
  const std::vector<uint8_t> sets{uint8_t(sourceSet(1, 7)), uint8_t(sourceSet(1, 8))};
  const VertexS vs = transfers.s();
  for (size_t slot = 0; slot < 5; ++slot) {
    const uint32_t rv = transfers.frameVertices()[slot];
    std::vector<core::Rgb16> want(2);
    intensityTransfers(glm::dvec3(s.bundle.transfers.vertexRadiance[rv]),
                       std::span(expected).subspan(2 * slot, 2), sets, s.bundle.tone, want);
    EXPECT_EQ(vs.vertexSlot[rv], slot);
    EXPECT_EQ(vs.receiverS[2 * slot], want[0]) << "slot " << slot;
    EXPECT_EQ(vs.receiverS[2 * slot + 1], want[1]) << "slot " << slot;
  }
  EXPECT_EQ(vs.receiverVertexOf[5], kNoIndex);
  EXPECT_EQ(transfers.gradedVertices(), 0u);

  // The product: k0 = sources 0 + 2, k1 = source 1, per vertex.
  ASSERT_EQ(transfers.productVertices(), 2u);
  const auto& row = s.productSourceTransfers;
  const std::vector<glm::dvec3> product{zero + row[0] + row[4], zero + row[2],
                                        zero + row[1] + row[5], zero + row[3]};
  const std::span<const glm::dvec3> pt = transfers.productTransfers();
  EXPECT_EQ(std::vector<glm::dvec3>(pt.begin(), pt.end()), product);
  for (size_t v = 0; v < 2; ++v) {
    std::vector<core::Rgb16> want(2);
    intensityTransfers(s.productRadiance[v], std::span(product).subspan(2 * v, 2), sets,
                       s.bundle.tone, want);
    EXPECT_EQ(vs.productS[2 * v], want[0]);
    EXPECT_EQ(vs.productS[2 * v + 1], want[1]);
  }

  // Probes: the receiver vertices by slot, then the product's vertices.
  const std::span<const core::Vec3> probes = transfers.probes();
  ASSERT_EQ(probes.size(), 7u);
  EXPECT_EQ(probes[0], s.bundle.view.staticMesh.positions[1]);
  EXPECT_EQ(probes[4], s.bundle.view.staticMesh.positions[3]);
  EXPECT_EQ(probes[6], s.productPositions[1]);
}

TEST(ClusterTransfers, MeasuredSharesGradeTheNextFrame) {
  const Strip s;
  ClusterTransfers transfers(s.bundle, s.mesh, {1, true, true, TransferKind::kFineLevels});
  OcclusionFeedback feedback(5, 3, true);
  feedback.productPlaced(2);
  const std::vector<uint32_t> receivers{1, 0};
  transfers.compute(receivers, s.selection, 1, s.product(), feedback);
  // Every probe fully occluded by both passes.
  const std::vector<uint32_t> passCluster{0, 1};
  feedback.observe(std::vector<uint8_t>(7 * 2, 255),
                   {passCluster, &s.selection, transfers.frameVertices(),
                    transfers.receiverTransfers(), transfers.productTransfers(), 2});
  transfers.compute(receivers, s.selection, 2, s.product(), feedback);
  EXPECT_EQ(transfers.gradedVertices(), 7u);
  const std::vector<double> q{1.0, 1.0};
  for (size_t slot = 0; slot < 5; ++slot) {
    const uint32_t rv = transfers.frameVertices()[slot];
    std::vector<core::Rgb16> want(2);
    intensityTransfersForOcclusions(glm::dvec3(s.bundle.transfers.vertexRadiance[rv]),
                                    transfers.receiverTransfers().subspan(2 * slot, 2), q,
                                    s.bundle.tone, want);
    EXPECT_EQ(transfers.s().receiverS[2 * slot], want[0]) << "slot " << slot;
    EXPECT_EQ(transfers.s().receiverS[2 * slot + 1], want[1]) << "slot " << slot;
  }
  // Graded transfers off: Fig. 4's sets whatever was measured.
  ClusterTransfers fig4(s.bundle, s.mesh, {1, false, true, TransferKind::kFineLevels});
  fig4.compute(receivers, s.selection, 3, s.product(), feedback);
  EXPECT_EQ(fig4.gradedVertices(), 0u);
}

TEST(ClusterTransfers, WithoutSelfShadowingTheProductHasNoVertices) {
  const Strip s;
  ClusterTransfers transfers(s.bundle, s.mesh, {1, true, false, TransferKind::kFineLevels});
  OcclusionFeedback feedback(5, 3, true);
  feedback.productPlaced(2);
  transfers.compute(std::vector<uint32_t>{0}, s.selection, 1, s.product(), feedback);
  EXPECT_EQ(transfers.frameVertices().size(), 4u);
  EXPECT_EQ(transfers.productVertices(), 0u);
  EXPECT_TRUE(transfers.s().productS.empty());
  EXPECT_EQ(transfers.probes().size(), 4u);
}

// Linear accumulation (the default): each cluster's share of the vertex's light, the same
// whatever was measured, and the whole-level kind: Fig. 4's codes as 8.8.
TEST(ClusterTransfers, LightSharesAndWholeLevels) {
  const Strip s;
  ClusterTransfers shares(s.bundle, s.mesh, {});
  ClusterTransfers whole(s.bundle, s.mesh, {1, true, true, TransferKind::kWholeLevels});
  OcclusionFeedback feedback(5, 3, true);
  feedback.productPlaced(2);
  const std::vector<uint32_t> receivers{1, 0};
  shares.compute(receivers, s.selection, 1, s.product(), feedback);
  whole.compute(receivers, s.selection, 1, s.product(), feedback);
  const std::vector<uint8_t> sets{uint8_t(sourceSet(1, 7)), uint8_t(sourceSet(1, 8))};
  for (size_t slot = 0; slot < 5; ++slot) {
    const uint32_t rv = shares.frameVertices()[slot];
    const glm::dvec3 total(s.bundle.transfers.vertexRadiance[rv]);
    const auto row = shares.receiverTransfers().subspan(2 * slot, 2);
    std::vector<core::Rgb16> want(2);
    lightShares(total, row, want);
    EXPECT_EQ(shares.s().receiverS[2 * slot], want[0]) << "slot " << slot;
    EXPECT_EQ(shares.s().receiverS[2 * slot + 1], want[1]) << "slot " << slot;
    for (size_t k = 0; k < 2; ++k) {
      const double expected = row[k].y / total.y;
      EXPECT_NEAR(want[k].g / double(core::kMaxFineLevel), std::min(expected, 1.0), 1e-4);
    }
    std::vector<core::Rgb8> codes(2);
    intensityTransfers(total, row, sets, s.bundle.tone, codes);
    EXPECT_EQ(whole.s().receiverS[2 * slot], core::Rgb16::fromLevels(codes[0])) << slot;
    EXPECT_EQ(whole.s().receiverS[2 * slot + 1], core::Rgb16::fromLevels(codes[1])) << slot;
  }
}

// The product's light shares: each cluster's sources summed in selection order, then
// lightShares; kept while the product's light (its generation) and the clusters' sources
// stay, taken again when either changes.
TEST(ClusterTransfers, ProductLightSharesAreKeptOnlyWhileLightAndSourcesStay) {
  const Strip s;
  ClusterTransfers shares(s.bundle, s.mesh, {});
  OcclusionFeedback feedback(5, 3, true);
  feedback.productPlaced(2);
  const std::vector<uint32_t> receivers{1, 0};
  const auto expect = [&](const std::vector<glm::dvec3>& radiance,
                          const std::vector<glm::dvec3>& rows, const ClusterSelection& selection,
                          const char* what) {
    const size_t clusters = selection.clusters.size();
    ASSERT_EQ(shares.s().productS.size(), 2 * clusters) << what;
    EXPECT_TRUE(shares.productTransfers().empty()) << "light shares keep no transfers";
    for (size_t v = 0; v < 2; ++v) {
      std::vector<glm::dvec3> sums(clusters, glm::dvec3(0.0));
      for (size_t k = 0; k < clusters; ++k) {
        const SourceCluster& cl = selection.clusters[k];
        for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
          sums[k] += rows[selection.sources[i] * 2 + v];
        }
      }
      std::vector<core::Rgb16> want(clusters);
      lightShares(radiance[v], sums, want);
      for (size_t k = 0; k < clusters; ++k) {
        EXPECT_EQ(shares.s().productS[v * clusters + k], want[k]) << what << ", v " << v;
      }
    }
  };
  ProductLight light = s.product();
  light.generation = 1;
  shares.compute(receivers, s.selection, 1, light, feedback);
  expect(s.productRadiance, s.productSourceTransfers, s.selection, "first frame");

  // Same generation and sources: the S stay the first frame's, even though (against the
  // contract, to show it) the rows changed.
  std::vector<glm::dvec3> rows = s.productSourceTransfers;
  rows[0] = glm::dvec3(1.0);
  light.sourceTransfers = rows;
  shares.compute(receivers, s.selection, 2, light, feedback);
  expect(s.productRadiance, s.productSourceTransfers, s.selection, "kept");

  light.generation = 2;  // shaded again
  shares.compute(receivers, s.selection, 3, light, feedback);
  expect(s.productRadiance, rows, s.selection, "new generation");

  // The same sources split otherwise, under the same generation: k0 = {0}, k1 = {2, 1}.
  ClusterSelection swapped = s.selection;
  swapped.clusters[0].sourceCount = 1;
  swapped.clusters[1].firstSource = 1;
  swapped.clusters[1].sourceCount = 2;
  swapped.sources = {0, 2, 1};
  shares.compute(receivers, swapped, 4, light, feedback);
  expect(s.productRadiance, rows, swapped, "other clusters");

  light.generation = 0;  // unknown: always taken again
  light.sourceTransfers = s.productSourceTransfers;
  shares.compute(receivers, swapped, 5, light, feedback);
  expect(s.productRadiance, s.productSourceTransfers, swapped, "generation 0");
}

}  // namespace
}  // namespace penumbra::shadow
