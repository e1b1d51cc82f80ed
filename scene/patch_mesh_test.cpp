#include "scene/patch_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "scene/camera.h"

namespace penumbra::scene {
namespace {

RoomDescription testRoom() {
  RoomDescription room;
  const uint32_t floor = room.addRoomShell(
      Aabb{glm::dvec3(0), glm::dvec3(6, 3, 5)}, Material{glm::dvec3(0.4), glm::dvec3(0)},
      Material{glm::dvec3(0.7), glm::dvec3(0)}, Material{glm::dvec3(0.8), glm::dvec3(0)});
  Quad& ceiling = room.quads[floor + 1];
  ceiling.regions.push_back(
      Region{"light", 0.3, 0.4, 0.3, 0.42, Material{glm::dvec3(0), glm::dvec3(10)}, 0.2});
  room.addSolidBox("desk", Aabb{glm::dvec3(4, 0, 3), glm::dvec3(5.5, 0.75, 4)},
                   Material{glm::dvec3(0.5), glm::dvec3(0)}, false);
  return room;
}

TEST(PatchMesh, ShellNormalsFaceIntoTheRoom) {
  const RoomDescription room = testRoom();
  const glm::dvec3 inside(3, 1.5, 2.5);
  for (size_t i = 0; i < 6; ++i) {
    const Quad& q = room.quads[i];
    const glm::dvec3 c = q.point(0.5, 0.5);
    EXPECT_GT(glm::dot(q.normal(), inside - c), 0) << q.name;
  }
  // Desk faces point away from the desk's centre (into the room's air).
  const glm::dvec3 deskCentre(4.75, 0.375, 3.5);
  for (size_t i = 6; i < room.quads.size(); ++i) {
    const Quad& q = room.quads[i];
    EXPECT_LT(glm::dot(q.normal(), deskCentre - q.point(0.5, 0.5)), 0) << q.name;
  }
}

TEST(PatchMesh, PatchAreasSumToQuadAreas) {
  const RoomDescription room = testRoom();
  const PatchMesh mesh = buildPatchMesh(room, 0.45);
  std::vector<double> sums(room.quads.size(), 0.0);
  for (const Patch& p : mesh.patches) sums[p.quad] += p.area;
  for (size_t i = 0; i < room.quads.size(); ++i) {
    EXPECT_NEAR(sums[i], room.quads[i].area(), 1e-9 * room.quads[i].area()) << room.quads[i].name;
  }
}

TEST(PatchMesh, TrianglesMatchPatches) {
  const PatchMesh mesh = buildPatchMesh(testRoom(), 0.45);
  ASSERT_EQ(mesh.triangleCount(), 2 * mesh.patches.size());
  ASSERT_EQ(mesh.trianglePatch.size(), mesh.triangleCount());
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
    const Patch& p = mesh.patches[mesh.trianglePatch[t]];
    EXPECT_EQ(p.firstTriangle, t - t % 2);
    const glm::dvec3 a = mesh.positions[mesh.indices[3 * t]];
    const glm::dvec3 b = mesh.positions[mesh.indices[3 * t + 1]];
    const glm::dvec3 c = mesh.positions[mesh.indices[3 * t + 2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    // Counter-clockwise about the patch normal, and half the patch each.
    EXPECT_GT(glm::dot(n, p.normal), 0);
    EXPECT_NEAR(0.5 * glm::length(n), 0.5 * p.area, 1e-12);
  }
}

TEST(PatchMesh, PatchSizeAndRegions) {
  const RoomDescription room = testRoom();
  const PatchMesh mesh = buildPatchMesh(room, 0.45);
  double emittingArea = 0;
  for (const Patch& p : mesh.patches) {
    if (p.emits()) {
      emittingArea += p.area;
      EXPECT_LE(p.area, 0.2 * 0.2 + 1e-12);  // the region's own size
    } else {
      EXPECT_LE(p.area, 0.45 * 0.45 + 1e-12);
    }
  }
  // The region (0.6 m x 0.6 m of the 6 x 5 ceiling) is covered exactly by its patches.
  EXPECT_NEAR(emittingArea, 0.6 * 0.6, 1e-9);
}

// The patch's side lengths along its quad's edges (patches are grid cells of one quad).
glm::dvec2 patchSides(const PatchMesh& mesh, const Patch& p) {
  const uint32_t* t = &mesh.indices[3 * size_t{p.firstTriangle}];
  // Triangle v00, v10, v11 of the cell: the first two edges run along u and v.
  return {glm::length(mesh.positions[t[1]] - mesh.positions[t[0]]),
          glm::length(mesh.positions[t[2]] - mesh.positions[t[1]])};
}

TEST(PatchMesh, ContactRefinementCutsTheFloorFinerAroundABoxBase) {
  // The desk of testRoom() stands on the floor: x 4-5.5, z 3-4, 0.75 m high. Its band on
  // the floor is that footprint grown by 0.75 m, clipped by the room: x 3.25-6, z 2.25-4.75
  // (0.25 m short of the wall, more than a 0.1 m patch: not run on to it).
  RoomDescription room = testRoom();
  room.refineAroundSolids(0.1);
  ASSERT_EQ(room.quads[0].refinements.size(), 1u);  // the floor
  for (size_t i = 1; i < room.quads.size(); ++i) {
    // Walls and ceiling do not carry the desk; the desk's own faces have it behind them.
    EXPECT_TRUE(room.quads[i].refinements.empty()) << room.quads[i].name;
  }
  const PatchMesh mesh = buildPatchMesh(room, 0.45);
  const PatchMesh plain = buildPatchMesh(testRoom(), 0.45);
  size_t inBand = 0, outside = 0;
  for (const Patch& p : mesh.patches) {
    if (p.quad != 0) continue;
    const glm::dvec2 sides = patchSides(mesh, p);
    const bool bandX = p.centre.x > 3.25;
    const bool bandZ = p.centre.z > 2.25 && p.centre.z < 4.75;
    // Strips run across the quad: a patch is fine along x inside the band's x range and
    // along z inside its z range, wherever it is. The floor's u runs along z, v along x.
    EXPECT_LE(sides.x, (bandZ ? 0.1 : 0.45) + 1e-9);
    EXPECT_LE(sides.y, (bandX ? 0.1 : 0.45) + 1e-9);
    if (bandX && bandZ) {
      ++inBand;
      EXPECT_LE(std::max(sides.x, sides.y), 0.1 + 1e-9);
    } else if (!bandX && !bandZ) {
      ++outside;
      EXPECT_GT(std::max(sides.x, sides.y), 0.3);
    }
  }
  EXPECT_GT(inBand, 0u);
  EXPECT_GT(outside, 0u);
  // Only the floor changed, and its area is still covered exactly.
  EXPECT_GT(mesh.patches.size(), plain.patches.size());
  double floorArea = 0;
  for (const Patch& p : mesh.patches) floorArea += p.quad == 0 ? p.area : 0;
  EXPECT_NEAR(floorArea, 30.0, 1e-9);
  for (uint32_t q = 1; q < room.quads.size(); ++q) {
    size_t a = 0, b = 0;
    for (const Patch& p : mesh.patches) a += p.quad == q;
    for (const Patch& p : plain.patches) b += p.quad == q;
    EXPECT_EQ(a, b) << room.quads[q].name;
  }
}

TEST(PatchMesh, ContactRefinementNeedsABoxOnTheQuad) {
  RoomDescription room;
  room.addRoomShell(Aabb{glm::dvec3(0), glm::dvec3(4, 3, 4)}, Material{}, Material{}, Material{});
  // A shelf hanging 1 m above the floor, touching no quad but its own.
  room.addSolidBox("shelf", Aabb{glm::dvec3(1, 1, 1), glm::dvec3(2, 1.2, 2)}, Material{}, true);
  // A cabinet against the x = 4 wall: it stands on the floor and touches that wall, so both
  // get a band (the wall's: the footprint grown by the cabinet's 0.5 m depth).
  room.addSolidBox("cabinet", Aabb{glm::dvec3(3.5, 0, 1), glm::dvec3(4, 2, 2)}, Material{}, false);
  room.refineAroundSolids(0.2);
  EXPECT_EQ(room.quads[0].refinements.size(), 1u);  // floor: the cabinet only
  EXPECT_EQ(room.quads[3].refinements.size(), 1u);  // wall x = 4
  EXPECT_TRUE(room.quads[1].refinements.empty());   // ceiling
  EXPECT_TRUE(room.quads[2].refinements.empty());   // wall x = 0
  const Refinement& wall = room.quads[3].refinements[0];
  // wall_xmax: u along z, v along y (inwardFaces); z 1-2 grown by 0.5, y 0-2 grown by 0.5.
  EXPECT_NEAR(wall.s0, 0.5 / 4, 1e-12);
  EXPECT_NEAR(wall.s1, 2.5 / 4, 1e-12);
  EXPECT_NEAR(wall.t0, 0.0, 1e-12);
  EXPECT_NEAR(wall.t1, 2.5 / 3, 1e-12);  // 0.5 m below the ceiling: more than a patch
  // A crate at z 3.0-3.2, 0.7 m high: its band ends at z = 3.9, 0.1 m (less than a patch)
  // short of the floor's edge at z = 4, and runs on to it.
  RoomDescription near;
  near.addRoomShell(Aabb{glm::dvec3(0), glm::dvec3(4, 3, 4)}, Material{}, Material{}, Material{});
  near.addSolidBox("crate", Aabb{glm::dvec3(1, 0, 3.0), glm::dvec3(1.5, 0.7, 3.2)}, Material{},
                   false);
  near.refineAroundSolids(0.2);
  ASSERT_EQ(near.quads[0].refinements.size(), 1u);
  // Floor: u along z (2.3 .. 3.9, run on to 4), v along x (0.3 .. 2.2).
  EXPECT_NEAR(near.quads[0].refinements[0].s0, 2.3 / 4, 1e-12);
  EXPECT_EQ(near.quads[0].refinements[0].s1, 1.0);
  EXPECT_NEAR(near.quads[0].refinements[0].t0, 0.3 / 4, 1e-12);
  EXPECT_NEAR(near.quads[0].refinements[0].t1, 2.2 / 4, 1e-12);
  EXPECT_THROW(room.refineAroundSolids(0), std::invalid_argument);
  EXPECT_THROW(room.refineAroundSolids(std::nan("")), std::invalid_argument);
}

// The vertices of quad `q`'s patches, each distinct position once (T-junctions included).
size_t distinctVertices(const PatchMesh& mesh, uint32_t q, bool& duplicated) {
  std::vector<uint32_t> used;
  for (const Patch& p : mesh.patches) {
    if (p.quad != q) continue;
    for (uint32_t k = 0; k < 6; ++k) used.push_back(mesh.indices[3 * p.firstTriangle + k]);
  }
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<std::array<double, 3>> at;
  for (uint32_t v : used)
    at.push_back({mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z});
  std::sort(at.begin(), at.end());
  duplicated = std::adjacent_find(at.begin(), at.end()) != at.end();
  return used.size();
}

TEST(PatchMesh, ShadowBoundaryRefinementCutsOnlyWhereTheLightsAreHidden) {
  // testRoom()'s light panel (x 1.8-2.4, z 1.5-2.1, on the ceiling) and its desk (x 4-5.5,
  // z 3-4, 0.75 m high): the desk hides the panel from the floor behind it, on the side
  // away from the panel; the floor by the x = 0 wall sees the whole panel.
  RoomDescription room = testRoom();
  room.shadowBoundaryPatchSize = 0.1;
  const PatchMesh mesh = buildPatchMesh(room, 0.45);
  const PatchMesh plain = buildPatchMesh(testRoom(), 0.45);
  size_t fine = 0, lights = 0, plainLights = 0;
  for (const Patch& p : mesh.patches) {
    const glm::dvec2 sides = patchSides(mesh, p);
    // Cells are halved while they straddle and are larger than 0.1 m: never below half.
    EXPECT_GE(std::min(sides.x, sides.y), 0.05 - 1e-9);
    fine += std::max(sides.x, sides.y) <= 0.1 + 1e-9;
    lights += p.emits();
    // Nothing near the x = 0 wall has the desk between it and the panel: the grid's
    // 0.42 x 0.43 m cells stay whole there.
    if (p.quad == 0 && p.centre.x < 1.5) {
      EXPECT_GT(std::min(sides.x, sides.y), 0.4) << p.centre.x << " " << p.centre.z;
    }
  }
  for (const Patch& p : plain.patches) plainLights += p.emits();
  EXPECT_EQ(lights, plainLights);  // the lights themselves are never cut
  EXPECT_GT(fine, 0u);
  // Far fewer patches than cutting the whole floor that finely: 30 m^2 at 0.1 m = 3,000.
  EXPECT_LT(mesh.patches.size(), plain.patches.size() + 1000);
  // Areas still cover every quad exactly, and each position is one vertex.
  std::vector<double> sums(room.quads.size(), 0.0);
  for (const Patch& p : mesh.patches) sums[p.quad] += p.area;
  for (uint32_t q = 0; q < room.quads.size(); ++q) {
    EXPECT_NEAR(sums[q], room.quads[q].area(), 1e-9 * room.quads[q].area()) << room.quads[q].name;
    bool duplicated = false;
    distinctVertices(mesh, q, duplicated);
    EXPECT_FALSE(duplicated) << room.quads[q].name;
  }
  // Every vertex is used, and the build is deterministic.
  std::vector<bool> used(mesh.positions.size(), false);
  for (uint32_t v : mesh.indices) used[v] = true;
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
  const PatchMesh again = buildPatchMesh(room, 0.45);
  EXPECT_EQ(again.indices, mesh.indices);
  EXPECT_EQ(again.positions, mesh.positions);
}

TEST(PatchMesh, ShadowBoundaryRefinementKeepsTheGridWhereNothingIsHidden) {
  // Without solids the shell is convex: no light is hidden anywhere, no cell is cut, and
  // the mesh is the grid's, vertex for vertex.
  RoomDescription room;
  room.addRoomShell(Aabb{glm::dvec3(0), glm::dvec3(4, 3, 4)}, Material{}, Material{}, Material{});
  room.quads[1].regions.push_back(
      Region{"light", 0.4, 0.6, 0.4, 0.6, Material{glm::dvec3(0), glm::dvec3(10)}, 0.2});
  const PatchMesh plain = buildPatchMesh(room, 0.4);
  room.shadowBoundaryPatchSize = 0.05;
  const PatchMesh refined = buildPatchMesh(room, 0.4);
  EXPECT_EQ(refined.positions, plain.positions);
  EXPECT_EQ(refined.indices, plain.indices);
  EXPECT_EQ(refined.patches.size(), plain.patches.size());
}

TEST(PatchMesh, ShadowBoundaryRefinementPastThePatchLimitThrows) {
  RoomDescription room = testRoom();
  room.shadowBoundaryPatchSize = 0.02;
  const double gridPatches = static_cast<double>(buildPatchMesh(testRoom(), 0.45).patches.size());
  EXPECT_THROW(buildPatchMesh(room, 0.45, gridPatches + 10), std::length_error);
}

TEST(PatchMesh, RayHitsNearestQuad) {
  const RoomDescription room = testRoom();
  // Straight down onto the desk top from above it.
  auto hit = room.intersect(glm::dvec3(4.5, 2, 3.5), glm::dvec3(0, -1, 0), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->point.y, 0.75, 1e-12);
  EXPECT_EQ(room.quads[hit->quad].name, "desk_top");
  // Up into the ceiling light region.
  hit = room.intersect(glm::dvec3(2.1, 1, 1.8), glm::dvec3(0, 1, 0), 0, 100);
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(room.quads[hit->quad].materialAt(hit->s, hit->u).emits());
  EXPECT_TRUE(room.segmentBlocked(glm::dvec3(4.5, 2, 3.5), glm::dvec3(4.5, 0, 3.5)));
  EXPECT_FALSE(room.segmentBlocked(glm::dvec3(1, 0, 1), glm::dvec3(2, 3, 2)));
  // A point on the desk top sees the ceiling.
  EXPECT_FALSE(room.segmentBlocked(glm::dvec3(4.5, 0.75, 3.5), glm::dvec3(4.5, 3, 3.5)));
}

TEST(PatchMesh, FormFactorMatchesPointToPatchFarAway) {
  const glm::dvec3 x(0), n(0, 1, 0);
  const double f = pointToPatchFormFactor(x, n, glm::dvec3(0, 10, 0), glm::dvec3(0, -1, 0), 0.01);
  // The disc term changes it by A / (pi r^2) relative: 3e-5 here.
  EXPECT_NEAR(f, 0.01 / (std::numbers::pi * 100), 1e-4 * f);
  EXPECT_LE(pointToPatchFormFactor(x, n, glm::dvec3(0, 1e-6, 0), glm::dvec3(0, -1, 0), 1), 1.0);
  EXPECT_EQ(pointToPatchFormFactor(x, n, glm::dvec3(0, -1, 0), glm::dvec3(0, 1, 0), 1), 0.0);
}

TEST(Camera, ProjectsTargetToCentreAndDepthRange) {
  Camera cam;
  cam.eye = glm::dvec3(1, 2, 3);
  cam.target = glm::dvec3(4, 1, -2);
  cam.zNear = 0.5;
  cam.zFar = 40;
  const glm::dmat4 vp = cam.viewProj();
  const glm::dvec4 c = vp * glm::dvec4(cam.target, 1);
  EXPECT_NEAR(c.x / c.w, 0, 1e-12);
  EXPECT_NEAR(c.y / c.w, 0, 1e-12);
  const glm::dvec3 f = glm::normalize(cam.target - cam.eye);
  const glm::dvec4 pn = vp * glm::dvec4(cam.eye + cam.zNear * f, 1);
  const glm::dvec4 pf = vp * glm::dvec4(cam.eye + cam.zFar * f, 1);
  EXPECT_NEAR(pn.z / pn.w, -1, 1e-9);
  EXPECT_NEAR(pf.z / pf.w, 1, 1e-9);
  // Row-major export: element (r, c) at m[4r + c].
  const core::Mat4 m = toRasterMat4(vp);
  EXPECT_EQ(m.m[3 * 4 + 2], static_cast<float>(vp[2][3]));
  EXPECT_EQ(m.m[0 * 4 + 3], static_cast<float>(vp[3][0]));
}

TEST(Camera, RayDirectionMatchesProjection) {
  Camera cam;
  cam.eye = glm::dvec3(0.3, 1.6, 0.3);
  cam.target = glm::dvec3(3, 0.7, 2.5);
  cam.aspect = 640.0 / 480.0;
  const glm::dmat4 vp = cam.viewProj();
  for (const auto& [xw, yw] : {std::pair{10.5, 20.5}, std::pair{600.0, 470.0}}) {
    const glm::dvec3 p = cam.eye + 3.0 * cam.rayDirection(xw, yw, 640, 480);
    const glm::dvec4 c = vp * glm::dvec4(p, 1);
    EXPECT_NEAR((c.x / c.w) * 320 + 320, xw, 1e-9);
    EXPECT_NEAR(-(c.y / c.w) * 240 + 240, yw, 1e-9);
  }
}

}  // namespace
}  // namespace penumbra::scene
