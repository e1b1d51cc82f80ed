// The light a placed product may block, on the bundled showroom: the §8 clusters cover the
// §6.1 traversal's sources exactly once, at most n of them.
#include "shadow/blocked_light.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "shadow/product_placement.h"
#include "shadow/scene_bundle.h"
#include "tests/showroom_bundle.h"

namespace penumbra::shadow {
namespace {

struct Showroom {
  Showroom()
      : bundle(testing::showroomBundle()),
        mesh(patchMeshOf(bundle)),
        hierarchy(mesh, bundle.sets, bundle.transfers, {}) {}
  SceneBundle bundle;
  scene::PatchMesh mesh;
  ShaftHierarchy hierarchy;
};

std::vector<uint32_t> sorted(std::span<const uint32_t> v) {
  std::vector<uint32_t> s(v.begin(), v.end());
  std::sort(s.begin(), s.end());
  return s;
}

TEST(BlockedLight, ClustersCoverTheTraversedSourcesOnce) {
  const Showroom room;
  ProductPlacement placement(room.bundle.products);
  placement.place(room.bundle.startPose);
  BlockedLight light;
  uint32_t frame = 0;
  for (size_t passes : {size_t(1), size_t(5), size_t(10000)}) {
    light.find(room.hierarchy, placement.bounds(), ++frame, passes);
    const size_t sources = light.traversal.sources.size();
    ASSERT_GT(sources, 5u) << "the start pose stands in the light";
    EXPECT_FALSE(light.traversal.receivers.empty());
    EXPECT_EQ(light.selection.clusters.size(), std::min(passes, sources));
    EXPECT_EQ(sorted(light.selection.sources), sorted(light.traversal.sources));
    std::vector<uint32_t> once = sorted(light.traversal.sources);
    once.erase(std::unique(once.begin(), once.end()), once.end());
    EXPECT_EQ(once.size(), sources) << "each source listed once";
    EXPECT_GE(light.nsTraversal, 0);
    EXPECT_GE(light.nsClusters, 0);
  }
}

TEST(BlockedLight, AProductOutsideTheRoomBlocksNothing) {
  const Showroom room;
  ProductPlacement placement(room.bundle.products);
  placement.place({0, 100.0f, 100.0f, 0.0f, 0.0f});
  BlockedLight light;
  light.find(room.hierarchy, placement.bounds(), 1, 50);
  EXPECT_TRUE(light.traversal.sources.empty());
  EXPECT_TRUE(light.traversal.receivers.empty());
  EXPECT_TRUE(light.selection.clusters.empty());
}

}  // namespace
}  // namespace penumbra::shadow
