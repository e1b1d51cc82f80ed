#include "scene/patch_visibility.h"

#include <gtest/gtest.h>

namespace penumbra::scene {
namespace {

// A 5 x 3 x 4 m room with a floating box between the camera and the back wall (z = 0).
struct Room {
  RoomDescription room;
  uint32_t floor = 0;
  PatchMesh mesh;
  Camera camera;
};

Room makeRoom() {
  Room r;
  Material m;
  r.floor = r.room.addRoomShell({{0, 0, 0}, {5, 3, 4}}, m, m, m);
  r.room.addSolidBox("box", {{2.0, 1.0, 1.5}, {3.0, 2.0, 2.5}}, m, true);
  r.mesh = buildPatchMesh(r.room, 0.25);
  r.camera.eye = {2.5, 1.5, 3.8};
  r.camera.target = {2.5, 1.5, 0};
  r.camera.fovYDegrees = 60;
  r.camera.aspect = 4.0 / 3.0;
  return r;
}

size_t patchNear(const Room& r, uint32_t quad, const glm::dvec3& p) {
  for (size_t i = 0; i < r.mesh.patches.size(); ++i) {
    if (r.mesh.patches[i].quad == quad && glm::length(r.mesh.patches[i].centre - p) < 0.18) {
      return i;
    }
  }
  ADD_FAILURE() << "no patch near the point";
  return 0;
}

TEST(PatchVisibility, FrustumFacingAndOcclusion) {
  const Room r = makeRoom();
  const std::vector<uint8_t> vis = visiblePatches(r.mesh, r.camera, 640, 480, &r.room);
  const std::vector<uint8_t> noOcclusion = visiblePatches(r.mesh, r.camera, 640, 480, nullptr);
  ASSERT_EQ(vis.size(), r.mesh.patches.size());
  const uint32_t back = r.floor + 4, front = r.floor + 5;  // walls z = 0 and z = 4
  // Straight ahead on the back wall, hidden by the box; visible without occlusion.
  const size_t hidden = patchNear(r, back, {2.5, 1.5, 0});
  EXPECT_EQ(vis[hidden], 0);
  EXPECT_EQ(noOcclusion[hidden], 1);
  // Beside the box on the back wall: seen.
  EXPECT_EQ(vis[patchNear(r, back, {0.9, 1.5, 0})], 1);
  // The wall behind the camera: never.
  EXPECT_EQ(noOcclusion[patchNear(r, front, {2.5, 1.5, 4})], 0);
  // The floor right below the camera is outside the 60-degree frustum.
  EXPECT_EQ(noOcclusion[patchNear(r, r.floor, {2.5, 0, 3.8})], 0);
  // The box's front face (z = 2.5, facing the camera) is seen, its back face is not.
  size_t boxFront = 0, boxBack = 0, seenBoxFront = 0, seenBoxBack = 0;
  for (size_t i = 0; i < r.mesh.patches.size(); ++i) {
    const Patch& p = r.mesh.patches[i];
    if (p.quad < r.floor + 6) continue;
    if (p.normal.z > 0.5) {
      ++boxFront;
      seenBoxFront += vis[i];
    }
    if (p.normal.z < -0.5) {
      ++boxBack;
      seenBoxBack += vis[i];
    }
  }
  EXPECT_GT(boxFront, 0u);
  EXPECT_EQ(seenBoxFront, boxFront);
  EXPECT_EQ(seenBoxBack, 0u);
  EXPECT_GT(boxBack, 0u);
  EXPECT_THROW(visiblePatches(r.mesh, r.camera, 0, 480, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::scene
