#include "lighting/radiance_transfer.h"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "lighting/embree_scene.h"
#include "lighting/form_factor.h"
#include "scene/camera.h"
#include "shadow/source_receiver_sets.h"

namespace penumbra::lighting {
namespace {

using glm::dvec3;

scene::Material diffuse(double r, double g, double b) {
  return {dvec3(r, g, b), dvec3(0.0)};
}
scene::Material emitter(const dvec3& radiance) {
  return {dvec3(0.0), radiance};
}

// A ceiling light of side `size` centred at (cx, cz) of the ceiling of `room`, one patch.
void addCeilingLight(scene::RoomDescription& room, uint32_t ceiling, double cx, double cz,
                     double size, const dvec3& radiance) {
  scene::Quad& c = room.quads[ceiling];
  const double lu = glm::length(c.edgeU), lv = glm::length(c.edgeV);
  // edgeU runs along +x and edgeV along +z from the origin corner (0, h, 0).
  c.regions.push_back(scene::Region{"light", (cx - size / 2) / lu, (cx + size / 2) / lu,
                                    (cz - size / 2) / lv, (cz + size / 2) / lv, emitter(radiance),
                                    size});
}

uint32_t vertexAt(const scene::PatchMesh& mesh, const dvec3& p) {
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    if (glm::length(mesh.positions[v] - p) < 1e-9) return v;
  }
  throw std::runtime_error("no vertex at the point");
}

std::vector<uint32_t> allPatches(const scene::PatchMesh& mesh) {
  std::vector<uint32_t> all(mesh.patches.size());
  for (uint32_t p = 0; p < all.size(); ++p) all[p] = p;
  return all;
}

std::vector<uint32_t> emitters(const scene::PatchMesh& mesh) {
  std::vector<uint32_t> out;
  for (uint32_t p = 0; p < mesh.patches.size(); ++p) {
    if (mesh.patches[p].emits()) out.push_back(p);
  }
  return out;
}

// A 4 x 3 x 4 room with white walls and one 0.4 m light in the middle of the ceiling;
// `blockers` become floating solid boxes.
struct LitRoom {
  scene::RoomDescription room;
  scene::PatchMesh mesh;
};

LitRoom litRoom(const std::vector<scene::Aabb>& blockers) {
  LitRoom r;
  const uint32_t floor =
      r.room.addRoomShell(scene::Aabb{dvec3(0), dvec3(4, 3, 4)}, diffuse(0.5, 0.4, 0.3),
                          diffuse(0.7, 0.7, 0.7), diffuse(0.8, 0.8, 0.8));
  addCeilingLight(r.room, floor + 1, 2.0, 2.0, 0.4, dvec3(10, 9, 8));
  for (const scene::Aabb& b : blockers)
    r.room.addSolidBox("blocker", b, diffuse(0.3, 0.3, 0.3), true);
  r.mesh = scene::buildPatchMesh(r.room, 0.5);
  return r;
}

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// ---------------------------------------------------------------------------------------
// EmbreeScene

TEST(EmbreeScene, OccludedAndIntersectSeeTheBlocker) {
  const LitRoom r = litRoom({scene::Aabb{dvec3(1.5, 1.0, 1.5), dvec3(2.5, 1.2, 2.5)}});
  const EmbreeScene rays(r.mesh);
  EXPECT_EQ(rays.triangleCount(), r.mesh.triangleCount());
  EXPECT_TRUE(rays.occluded(dvec3(2, 0.0, 2), dvec3(2, 3, 2)));
  EXPECT_FALSE(rays.occluded(dvec3(0.5, 0.0, 0.5), dvec3(0.5, 3.0, 0.5)));  // floor to ceiling
  const auto hit = rays.intersect(dvec3(2, 0.5, 2), dvec3(0, 1, 0));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.5, 1e-6);
  // The hit triangle is on the blocker's bottom face (facing -y).
  const scene::Patch& p = r.mesh.patches[r.mesh.trianglePatch[hit->triangle]];
  EXPECT_EQ(p.normal, dvec3(0, -1, 0));
  EXPECT_FALSE(rays.intersect(dvec3(2, 0.5, 2), dvec3(0, 1, 0), 0.0, 0.4).has_value());

  std::vector<Segment> segments{{dvec3(2, 0, 2), dvec3(2, 3, 2)},
                                {dvec3(0.5, 0, 0.5), dvec3(0.5, 3, 0.5)}};
  std::vector<uint8_t> out(2);
  rays.occluded(segments, out);
  EXPECT_EQ(out, (std::vector<uint8_t>{1, 0}));
  std::vector<uint8_t> wrong(1);
  EXPECT_THROW(rays.occluded(segments, wrong), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// Visibility and transfers

TEST(RadianceTransfer, BlockerGivesZeroAndHalfBlockerHalfVisibility) {
  const dvec3 x(2, 0, 2), n(0, 1, 0);
  for (const auto& [blocker, expected] :
       {std::pair{scene::Aabb{dvec3(1.5, 1.0, 1.5), dvec3(2.5, 1.2, 2.5)}, 0.0},
        std::pair{scene::Aabb{dvec3(2.0, 1.0, 1.5), dvec3(3.0, 1.2, 2.5)}, 0.5},
        std::pair{scene::Aabb{dvec3(3.0, 1.0, 3.0), dvec3(3.5, 1.2, 3.5)}, 1.0}}) {
    const LitRoom r = litRoom({blocker});
    const EmbreeScene rays(r.mesh);
    const std::vector<uint32_t> lights = emitters(r.mesh);
    ASSERT_EQ(lights.size(), 1u);
    const auto polygon = patchPolygon(r.mesh, lights[0]);
    // The light's edge x = 2.0 projects from x onto the blocker's edge x = 2.0: with a
    // 4 x 4 jittered grid exactly two columns of samples are hidden.
    EXPECT_DOUBLE_EQ(pointToPatchVisibility(rays, x, n, polygon, 4, 1234, 1e-4), expected);

    TransferOptions options;
    options.relativeThreshold = 0;
    const shadow::SourceReceiverSets sets{lights, allPatches(r.mesh), 1.0};
    const shadow::RadianceTransfers t = computeRadianceTransfers(r.mesh, sets, rays, options);
    const uint32_t vertex = vertexAt(r.mesh, x);
    const auto it = std::lower_bound(t.receiverVertices.begin(), t.receiverVertices.end(), vertex);
    ASSERT_NE(it, t.receiverVertices.end());
    const uint32_t i = static_cast<uint32_t>(it - t.receiverVertices.begin());
    const dvec3 unblocked =
        dvec3(0.5, 0.4, 0.3) * dvec3(10, 9, 8) * pointToPolygonFormFactor(x, n, polygon);
    const glm::vec3 expectedRadiance(unblocked * expected);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(t.vertexRadiance[i][c], expectedRadiance[c]);
    bool found = false;
    for (uint32_t e = t.sourceStart[0]; e < t.sourceStart[1]; ++e) {
      if (t.entryVertex[e] != i) continue;
      found = true;
      for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(t.entryTransfer[e][c], expectedRadiance[c]);
    }
    EXPECT_EQ(found, expected > 0);
  }
}

TEST(RadianceTransfer, ReciprocityBetweenFloorAndCeilingPatches) {
  // A_i F_ij = A_j F_ji, each patch-to-patch form factor the area mean of the analytic
  // point-to-polygon one (midpoint rule).
  const LitRoom r = litRoom({});
  const uint32_t light = emitters(r.mesh)[0];
  const auto integrate = [&](uint32_t from, uint32_t to) {
    const auto a = patchPolygon(r.mesh, from), b = patchPolygon(r.mesh, to);
    const dvec3 u = a[1] - a[0], v = a[3] - a[0];
    const int k = 16;
    double sum = 0;
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i < k; ++i) {
        const dvec3 x = a[0] + ((i + 0.5) / k) * u + ((j + 0.5) / k) * v;
        sum += pointToPolygonFormFactor(x, r.mesh.patches[from].normal, b);
      }
    }
    return sum / (k * k) * r.mesh.patches[from].area;
  };
  for (uint32_t p = 0; p < r.mesh.patches.size(); ++p) {
    if (r.mesh.patches[p].normal != dvec3(0, 1, 0) && r.mesh.patches[p].normal != dvec3(1, 0, 0)) {
      continue;  // floor and one wall
    }
    const double aij = integrate(p, light), aji = integrate(light, p);
    EXPECT_NEAR(aij / aji, 1.0, 1e-3) << "patch " << p;  // measured within 2e-4
  }
}

TEST(RadianceTransfer, ClosedRoomCatchesAllTheEmittedLight) {
  // White (rho = 1) closed room, no blockers: the receiver-area-weighted sum of the
  // transfers from the light is sum_i A_i F_ij L_j = A_j L_j sum_i F_ji = A_j L_j.
  scene::RoomDescription room;
  const uint32_t floor = room.addRoomShell(scene::Aabb{dvec3(0), dvec3(2, 2, 2)}, diffuse(1, 1, 1),
                                           diffuse(1, 1, 1), diffuse(1, 1, 1));
  addCeilingLight(room, floor + 1, 1.0, 1.0, 0.5, dvec3(2.0));
  const scene::PatchMesh mesh = scene::buildPatchMesh(room, 0.125);
  const EmbreeScene rays(mesh);
  const std::vector<uint32_t> lights = emitters(mesh);
  ASSERT_EQ(lights.size(), 16u);  // the 0.5 m light in 0.125 m patches
  TransferOptions options;
  options.relativeThreshold = 0;
  options.threads = 2;
  const shadow::SourceReceiverSets sets{lights, allPatches(mesh), 1.0};
  const shadow::RadianceTransfers t = computeRadianceTransfers(mesh, sets, rays, options);
  // Each vertex stands for a quarter of each patch it is a corner of (trapezoid rule).
  std::vector<double> vertexArea(mesh.positions.size(), 0.0);
  for (uint32_t p = 0; p < mesh.patches.size(); ++p) {
    const size_t tri = mesh.patches[p].firstTriangle;
    for (size_t k : {0, 1, 2, 5}) vertexArea[mesh.indices[3 * tri + k]] += mesh.patches[p].area / 4;
  }
  double caught = 0;
  for (size_t s = 0; s < t.sourceCount(); ++s) {
    for (uint32_t e = t.sourceStart[s]; e < t.sourceStart[s + 1]; ++e) {
      caught += vertexArea[t.receiverVertices[t.entryVertex[e]]] * t.entryTransfer[e].x;
    }
  }
  const double emitted = 0.5 * 0.5 * 2.0;
  EXPECT_NEAR(caught / emitted, 1.0, 0.01);  // measured 0.9964
}

TEST(RadianceTransfer, TotalRadianceBoundsTheSourceTransfers) {
  const LitRoom base = litRoom({scene::Aabb{dvec3(1.0, 0.8, 1.0), dvec3(2.2, 1.0, 1.8)}});
  scene::RoomDescription room = base.room;
  addCeilingLight(room, 1, 0.8, 3.0, 0.4, dvec3(3, 3, 3));
  addCeilingLight(room, 1, 3.2, 0.8, 0.4, dvec3(1, 2, 6));
  const scene::PatchMesh mesh = scene::buildPatchMesh(room, 0.4);
  const EmbreeScene rays(mesh);
  std::vector<uint8_t> visible(mesh.patches.size(), 1);
  const shadow::SourceReceiverSets sets = shadow::selectSourcesAndReceivers(mesh, visible, 0.7);
  ASSERT_LT(sets.sources.size(), emitters(mesh).size());
  const shadow::RadianceTransfers t = computeRadianceTransfers(mesh, sets, rays);
  std::vector<glm::dvec3> sum(t.receiverVertices.size(), glm::dvec3(0.0));
  for (size_t s = 0; s < t.sourceCount(); ++s) {
    for (uint32_t e = t.sourceStart[s]; e < t.sourceStart[s + 1]; ++e) {
      sum[t.entryVertex[e]] += glm::dvec3(t.entryTransfer[e]);
    }
  }
  for (size_t i = 0; i < sum.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(t.vertexRadiance[i][c], sum[i][c] * (1 - 1e-6)) << "vertex " << i;
    }
  }
  ASSERT_EQ(t.sourceAverage.size(), sets.sources.size());
  for (float a : t.sourceAverage) EXPECT_GT(a, 0.0f);
}

TEST(RadianceTransfer, SameBytesForAnyThreadCount) {
  const LitRoom base = litRoom({scene::Aabb{dvec3(1.0, 0.8, 1.0), dvec3(2.2, 1.0, 1.8)}});
  scene::RoomDescription room = base.room;
  addCeilingLight(room, 1, 0.8, 3.0, 0.4, dvec3(3, 3, 3));
  const scene::PatchMesh mesh = scene::buildPatchMesh(room, 0.4);
  const EmbreeScene rays(mesh);
  std::vector<uint8_t> visible(mesh.patches.size(), 0);
  for (size_t p = 0; p < visible.size(); p += 2) visible[p] = 1;
  const shadow::SourceReceiverSets sets = shadow::selectSourcesAndReceivers(mesh, visible, 1.0);
  TransferOptions one;
  one.threads = 1;
  TransferOptions three = one;
  three.threads = 3;
  const shadow::RadianceTransfers a = computeRadianceTransfers(mesh, sets, rays, one);
  const shadow::RadianceTransfers b = computeRadianceTransfers(mesh, sets, rays, three);
  EXPECT_FALSE(a.entryVertex.empty());
  EXPECT_TRUE(sameBytes(a.receiverVertices, b.receiverVertices));
  EXPECT_TRUE(sameBytes(a.vertexRadiance, b.vertexRadiance));
  EXPECT_TRUE(sameBytes(a.sourceStart, b.sourceStart));
  EXPECT_TRUE(sameBytes(a.entryVertex, b.entryVertex));
  EXPECT_TRUE(sameBytes(a.entryTransfer, b.entryTransfer));
  EXPECT_TRUE(sameBytes(a.sourceAverage, b.sourceAverage));
  // A different seed moves the jitter, so partly shadowed entries change.
  TransferOptions reseeded = one;
  reseeded.seed = 99;
  EXPECT_FALSE(sameBytes(a.entryTransfer,
                         computeRadianceTransfers(mesh, sets, rays, reseeded).entryTransfer));
}

TEST(RadianceTransfer, InvalidOptionsThrow) {
  const LitRoom r = litRoom({});
  const EmbreeScene rays(r.mesh);
  const shadow::SourceReceiverSets sets{emitters(r.mesh), {0, 1}, 1.0};
  TransferOptions bad;
  bad.samplesPerSide = 0;
  EXPECT_THROW(computeRadianceTransfers(r.mesh, sets, rays, bad), std::invalid_argument);
  bad = {};
  bad.relativeThreshold = -1;
  EXPECT_THROW(computeRadianceTransfers(r.mesh, sets, rays, bad), std::invalid_argument);
  const shadow::SourceReceiverSets outOfRange{
      {static_cast<uint32_t>(r.mesh.patches.size())}, {}, 1.0};
  EXPECT_THROW(computeRadianceTransfers(r.mesh, outOfRange, rays), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// Camera visibility

TEST(CameraVisibility, SeesTheFrontWallNotTheBackWall) {
  const LitRoom r = litRoom({});
  scene::Camera camera;
  camera.eye = dvec3(2, 1.5, 3.5);
  camera.target = dvec3(2, 1.5, 0);  // looking down -z at the wall z = 0
  camera.fovYDegrees = 40;
  camera.aspect = 1;
  const std::vector<uint8_t> visible = patchesVisibleFromCamera(r.mesh, camera.viewProj(), 64, 64);
  ASSERT_EQ(visible.size(), r.mesh.patches.size());
  size_t front = 0, back = 0;
  for (uint32_t p = 0; p < r.mesh.patches.size(); ++p) {
    if (r.mesh.patches[p].normal == dvec3(0, 0, 1)) front += visible[p];  // wall z = 0
    if (r.mesh.patches[p].normal == dvec3(0, 0, -1)) back += visible[p];  // wall z = 4
  }
  EXPECT_GT(front, 0u);
  EXPECT_EQ(back, 0u);
  EXPECT_THROW(patchesVisibleFromCamera(r.mesh, camera.viewProj(), 0, 64), std::invalid_argument);
  EXPECT_THROW(patchesVisibleFromCamera(r.mesh, glm::dmat4(0.0), 8, 8), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------
// The synthetic showroom of shadow/synthetic_traces.cpp (6 x 3 x 5 m, four ceiling panels, a
// window, a desk; 0.45 m patches; 640 x 480 camera), end to end (timed in
// bench/shading_bench.cpp).

scene::Region regionMetres(const scene::Quad& q, double u0, double u1, double v0, double v1,
                           const scene::Material& m, double patchSize) {
  const double lu = glm::length(q.edgeU), lv = glm::length(q.edgeV);
  return scene::Region{"region", u0 / lu, u1 / lu, v0 / lv, v1 / lv, m, patchSize};
}

TEST(RadianceTransfer, ShowroomEndToEnd) {
  scene::RoomDescription room;
  const uint32_t floor =
      room.addRoomShell(scene::Aabb{dvec3(0, 0, 0), dvec3(6, 3, 5)}, diffuse(0.45, 0.38, 0.30),
                        diffuse(0.72, 0.71, 0.68), diffuse(0.80, 0.80, 0.80));
  scene::Quad& c = room.quads[floor + 1];
  for (double px : {1.8, 3.6}) {
    for (double pz : {1.4, 3.0}) {
      c.regions.push_back(
          regionMetres(c, px, px + 0.6, pz, pz + 0.6, emitter(dvec3(14.0, 13.0, 11.5)), 0.2));
    }
  }
  scene::Quad& w = room.quads[floor + 5];
  w.regions.push_back(regionMetres(w, 0.9, 2.1, 2.7, 4.3, emitter(dvec3(5.0, 6.0, 7.5)), 0.2));
  room.addSolidBox("desk", scene::Aabb{dvec3(4.4, 0, 3.4), dvec3(5.8, 0.75, 4.2)},
                   diffuse(0.50, 0.33, 0.20), false);
  scene::Camera camera;
  camera.eye = dvec3(0.35, 1.6, 0.35);
  camera.target = dvec3(3.2, 0.7, 2.8);
  camera.fovYDegrees = 60;
  camera.aspect = 640.0 / 480.0;
  camera.zNear = 0.05;
  camera.zFar = 15;
  const scene::PatchMesh mesh = scene::buildPatchMesh(room, 0.45);

  const EmbreeScene rays(mesh);
  const std::vector<uint8_t> visible =
      patchesVisibleFromCamera(mesh, rays, camera.viewProj(), 640, 480);
  const shadow::SourceReceiverSets sets = shadow::selectSourcesAndReceivers(mesh, visible, 0.7);
  TransferOptions options;
  options.threads = 2;
  const shadow::RadianceTransfers t = computeRadianceTransfers(mesh, sets, rays, options);
  EXPECT_GT(sets.sources.size(), 0u);
  EXPECT_GT(t.entryVertex.size(), 0u);
}

}  // namespace
}  // namespace penumbra::lighting
