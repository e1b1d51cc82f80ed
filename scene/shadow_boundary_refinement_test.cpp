#include "scene/shadow_boundary_refinement.h"

#include <gtest/gtest.h>

#include <vector>

namespace penumbra::scene {
namespace {

// A 4 x 3 x 4 m room with a 1 m high box at x 2.5-3, z 1.5-2.5 and a small light just
// under the ceiling above (2, 2.9, 2). The box's far top edge (x = 3, y = 1) throws the
// edge of its shadow onto the floor at x = 2 + 1 * 2.9 / 1.9 = 3.526.
RoomDescription boxRoom() {
  RoomDescription room;
  room.addRoomShell(Aabb{glm::dvec3(0), glm::dvec3(4, 3, 4)}, Material{}, Material{}, Material{});
  room.addSolidBox("box", Aabb{glm::dvec3(2.5, 0, 1.5), glm::dvec3(3, 1, 2.5)}, Material{}, false);
  return room;
}

LightSample pointLight(const glm::dvec3& at, double power) {
  return LightSample{at, glm::dvec3(0, -1, 0), 1e-4, power};
}

// The floor cell over world x [x0, x1], z [z0, z1] (the floor's u runs along z, v along x).
bool floorCellStraddles(const ShadowBoundaryTest& test, const RoomDescription& room, double x0,
                        double x1, double z0, double z1) {
  const Quad& floor = room.quads[0];
  const glm::dvec3 corner = floor.point(z0 / 4, x0 / 4);
  EXPECT_DOUBLE_EQ(corner.x, x0);
  EXPECT_DOUBLE_EQ(corner.z, z0);
  return test.straddles(floor, z0 / 4, z1 / 4, x0 / 4, x1 / 4);
}

TEST(ShadowBoundaryTest, SplitsOnlyCellsTheShadowEdgeCrosses) {
  const RoomDescription room = boxRoom();
  const ShadowBoundaryTest test(room, {pointLight({2, 2.9, 2}, 1.0)}, 0.02);
  EXPECT_TRUE(floorCellStraddles(test, room, 3.4, 3.7, 1.9, 2.1));   // the edge at 3.526
  EXPECT_FALSE(floorCellStraddles(test, room, 3.1, 3.4, 1.9, 2.1));  // wholly in the shadow
  EXPECT_FALSE(floorCellStraddles(test, room, 3.6, 3.9, 1.9, 2.1));  // wholly lit
  EXPECT_FALSE(floorCellStraddles(test, room, 0.5, 0.8, 0.5, 0.8));  // far from the box
}

TEST(ShadowBoundaryTest, IgnoresTheEdgeOfAnInsignificantLight) {
  // A second light over the other side, (3.9, 2.9, 2), throws the box's near top edge
  // (x = 2.5, y = 1) onto the floor at x = 3.9 - 1.4 * 2.9 / 1.9 = 1.763. The bright light
  // at (1.1, 2.9, 2) lights the whole cell x 1.7-1.85 (the box is beyond it), so the cell
  // straddles only the second light's edge, and that light's power decides.
  const RoomDescription room = boxRoom();
  const LightSample bright = pointLight({1.1, 2.9, 2}, 1.0);
  const LightSample other = pointLight({3.9, 2.9, 2}, 1.0);
  EXPECT_TRUE(
      floorCellStraddles(ShadowBoundaryTest(room, {other}, 0.02), room, 1.7, 1.85, 1.9, 2.1));
  EXPECT_FALSE(
      floorCellStraddles(ShadowBoundaryTest(room, {bright}, 0.02), room, 1.7, 1.85, 1.9, 2.1));
  // Scale the second light to 1 % and to 5 % of the bright one's light at the cell's centre.
  const glm::dvec3 centre(1.775, 1e-4, 2.0), up(0, 1, 0);
  const double fromBright =
      pointToPatchFormFactor(centre, up, bright.centre, bright.normal, bright.area);
  const double fromOther =
      pointToPatchFormFactor(centre, up, other.centre, other.normal, other.area);
  ASSERT_GT(fromOther, 0);
  LightSample onePercent = other, fivePercent = other;
  onePercent.power = 0.01 * fromBright / fromOther;
  fivePercent.power = 0.05 * fromBright / fromOther;
  EXPECT_FALSE(floorCellStraddles(ShadowBoundaryTest(room, {bright, onePercent}, 0.02), room, 1.7,
                                  1.85, 1.9, 2.1));
  EXPECT_TRUE(floorCellStraddles(ShadowBoundaryTest(room, {bright, fivePercent}, 0.02), room, 1.7,
                                 1.85, 1.9, 2.1));
}

TEST(ShadowBoundaryTest, ALightBehindTheSurfaceIsNoBoundary) {
  // A light in the floor's plane's far side sends nothing to any point of the floor: no
  // point is lit, none hidden.
  const RoomDescription room = boxRoom();
  const ShadowBoundaryTest test(room, {pointLight({3.2, -0.5, 2}, 1.0)}, 0.02);
  EXPECT_FALSE(floorCellStraddles(test, room, 3.4, 3.7, 1.9, 2.1));
}

}  // namespace
}  // namespace penumbra::scene
