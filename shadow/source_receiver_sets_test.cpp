#include "shadow/source_receiver_sets.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <vector>

namespace penumbra::shadow {
namespace {

// Only the patch list matters to the set selection.
scene::PatchMesh meshWithPatches(const std::vector<std::pair<double, double>>& emissionArea) {
  scene::PatchMesh mesh;
  for (const auto& [emission, area] : emissionArea) {
    scene::Patch p;
    p.emission = glm::dvec3(emission);
    p.area = area;
    mesh.patches.push_back(p);
  }
  return mesh;
}

TEST(SourceReceiverSets, PowerSharePicksTheShortestBrightPrefix) {
  // Powers (grey emission x area): patch 1 -> 5, patch 3 -> 3, patch 4 -> 2; 0 and 2 dark.
  const scene::PatchMesh mesh = meshWithPatches({{0, 1}, {2.5, 2}, {0, 3}, {3, 1}, {1, 2}});
  const std::vector<uint8_t> visible(mesh.patches.size(), 0);
  EXPECT_EQ(selectSourcesAndReceivers(mesh, visible, 0.45).sources, (std::vector<uint32_t>{1}));
  EXPECT_EQ(selectSourcesAndReceivers(mesh, visible, 0.55).sources, (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(selectSourcesAndReceivers(mesh, visible, 0.75).sources, (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(selectSourcesAndReceivers(mesh, visible, 0.85).sources,
            (std::vector<uint32_t>{1, 3, 4}));
  EXPECT_DOUBLE_EQ(selectSourcesAndReceivers(mesh, visible, 0.85).powerShare, 0.85);
}

TEST(SourceReceiverSets, FullShareTakesEveryEmitterEvenNegligibleOnes) {
  // The last emitter is far below the rounding of the total: only the explicit rule for
  // powerShare == 1 keeps it.
  const scene::PatchMesh mesh = meshWithPatches({{1e-30, 1}, {0, 1}, {4, 1}, {2, 1}});
  const std::vector<uint8_t> visible(mesh.patches.size(), 1);
  const SourceReceiverSets sets = selectSourcesAndReceivers(mesh, visible, 1.0);
  EXPECT_EQ(sets.sources, (std::vector<uint32_t>{2, 3, 0}));
  EXPECT_EQ(sets.receivers, (std::vector<uint32_t>{0, 1, 2, 3}));
}

TEST(SourceReceiverSets, TiesAreBrokenByPatchIndex) {
  const scene::PatchMesh mesh = meshWithPatches({{1, 2}, {2, 1}, {0, 1}, {1, 2}});
  const std::vector<uint8_t> visible(mesh.patches.size(), 0);
  EXPECT_EQ(selectSourcesAndReceivers(mesh, visible, 1.0).sources,
            (std::vector<uint32_t>{0, 1, 3}));
}

TEST(SourceReceiverSets, ReceiversAreTheVisiblePatches) {
  const scene::PatchMesh mesh = meshWithPatches({{0, 1}, {1, 1}, {0, 1}, {0, 1}});
  const std::vector<uint8_t> visible{0, 1, 0, 7};
  const SourceReceiverSets sets = selectSourcesAndReceivers(mesh, visible, 0.7);
  EXPECT_EQ(sets.receivers, (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(sets.sources, (std::vector<uint32_t>{1}));
}

TEST(SourceReceiverSets, NoEmittersGiveNoSources) {
  const scene::PatchMesh mesh = meshWithPatches({{0, 1}, {0, 1}});
  const std::vector<uint8_t> visible(2, 1);
  EXPECT_TRUE(selectSourcesAndReceivers(mesh, visible, 0.7).sources.empty());
}

TEST(SourceReceiverSets, InvalidInputsThrow) {
  const scene::PatchMesh mesh = meshWithPatches({{1, 1}, {0, 1}});
  const std::vector<uint8_t> visible(2, 1);
  for (double share : {0.0, -0.2, 1.0000001, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW(selectSourcesAndReceivers(mesh, visible, share), std::invalid_argument) << share;
  }
  const std::vector<uint8_t> shortVisible(1, 1);
  EXPECT_THROW(selectSourcesAndReceivers(mesh, shortVisible, 0.7), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
