// Live lighting's frame on the bundled showroom (issue 16 item 6): distant lights shade the
// product, and its shadows are cast by orthographic maps and subtracted through the same
// compositor and rasterizer as the captured sources'.
#include "shadow/environment_light_transfers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "shadow/frame_loop.h"
#include "shadow/light_frustum.h"
#include "shadow/product_shading.h"
#include "tests/showroom_bundle.h"

namespace penumbra::shadow {
namespace {

envmap::DirectionalLight light(uint32_t id, const glm::dvec3& towards, double power) {
  envmap::DirectionalLight l;
  l.id = id;
  l.direction = glm::normalize(towards);
  l.power = glm::dvec3(power);
  return l;
}

// The pixels a frame changed outside the product (those `productOnly`, a frame without
// lights, left at the background): their count and mean column.
struct Changed {
  size_t count = 0;
  double meanColumn = 0;
};

Changed shadowPixels(const SceneBundle& b, const std::vector<uint8_t>& lit,
                     const std::vector<uint8_t>& productOnly) {
  Changed c;
  for (size_t i = 0; i < lit.size() / 4; ++i) {
    if (productOnly[4 * i] != b.background[4 * i]) continue;  // the product itself
    if (lit[4 * i] == b.background[4 * i] && lit[4 * i + 1] == b.background[4 * i + 1] &&
        lit[4 * i + 2] == b.background[4 * i + 2]) {
      continue;
    }
    ++c.count;
    c.meanColumn += double(i % b.view.width);
  }
  if (c.count) c.meanColumn /= double(c.count);
  return c;
}

TEST(DirectionalFrustum, HoldsTheOccluderTightlyAndEveryReceiverInDepth) {
  scene::Aabb product{{2.8, 0.0, 2.2}, {3.2, 0.9, 2.6}};
  const scene::Aabb room{{0, 0, 0}, {6, 3, 5}};
  for (const glm::dvec3& towards : {glm::dvec3(0, 1, 0), glm::dvec3(1, 1, 0.3),
                                    glm::dvec3(-0.2, 0.05, -1), glm::dvec3(0, 0, 1)}) {
    const auto f = fitDirectionalFrustum(towards, product, room);
    ASSERT_TRUE(f.has_value());
    double extreme = 0;
    EXPECT_TRUE(f->orthographic);
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 p = product.corner(size_t(corner));
      const glm::dvec4 clip = f->viewProj * glm::dvec4(p, 1.0);
      EXPECT_DOUBLE_EQ(clip.w, 1.0);
      // Inside the window with its margin (3% of the extent: 1/1.06 of the half-width).
      EXPECT_LE(std::abs(clip.x), 1.0 / 1.06 + 1e-9);
      EXPECT_LE(std::abs(clip.y), 1.0 / 1.06 + 1e-9);
      extreme = std::max({extreme, std::abs(clip.x), std::abs(clip.y)});
      EXPECT_GT(clip.z, -1.0);
      EXPECT_LT(clip.z, 1.0);
      const glm::dvec3 q = room.corner(size_t(corner));
      EXPECT_LT((f->viewProj * glm::dvec4(q, 1.0)).z, 1.0) << "room corner beyond the far plane";
    }
    EXPECT_GT(extreme, 0.93) << "tight: a corner at the margin (the sphere's square: 0.4-0.8)";
    // Nearer the light is nearer in depth: the light looks along -towards.
    const glm::dvec3 c = product.centre(), d = glm::normalize(towards);
    EXPECT_LT((f->viewProj * glm::dvec4(c + 0.1 * d, 1.0)).z,
              (f->viewProj * glm::dvec4(c - 0.1 * d, 1.0)).z);
  }
  EXPECT_FALSE(fitDirectionalFrustum({0, 0, 0}, product, room).has_value());
  EXPECT_FALSE(fitDirectionalFrustum({0, 1, 0}, scene::Aabb::emptyBox(), room).has_value());
}

// Every receiver patch with a vertex inside a light's shadow cylinder is listed for that
// light (the octree walk is conservative), and the shares at a vertex are each light's
// cosine-weighted power over the sum.
TEST(EnvironmentLightTransfers, ListsEveryReceiverInTheShadowAndSharesTheLight) {
  const SceneBundle& b = testing::showroomBundle();
  const scene::PatchMesh mesh = patchMeshOf(b);
  const ShaftHierarchy hierarchy(mesh, b.sets, b.transfers);
  EnvironmentLightTransfers stage(b, mesh, hierarchy);
  const std::vector<glm::dvec3> towards = {glm::normalize(glm::dvec3(0, 1, 0)),
                                           glm::normalize(glm::dvec3(1, 0.6, 0.2)),
                                           glm::normalize(glm::dvec3(-0.3, 0.4, 1))};
  const std::vector<glm::dvec3> power = {glm::dvec3(1.0), glm::dvec3(0.5, 0.6, 0.7),
                                         glm::dvec3(2.0)};
  const scene::Aabb product{{2.8, 0.0, 2.2}, {3.2, 0.9, 2.6}};
  stage.compute({towards, power}, product, 1, {});
  const auto listed = [&](size_t k, uint32_t patch) {
    const auto start = stage.lightPatchStart();
    const auto patches = stage.receiverPatches();
    return std::find(patches.begin() + start[k], patches.begin() + start[k + 1], patch) !=
           patches.begin() + start[k + 1];
  };
  // q is in the product box's shadow of light k when the ray from q towards the light meets
  // the box (slab test).
  const auto inShadow = [&](const glm::dvec3& q, const glm::dvec3& d) {
    double near = 0, far = 1e300;
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0) {
        if (q[a] < product.min[a] || q[a] > product.max[a]) return false;
        continue;
      }
      double t0 = (product.min[a] - q[a]) / d[a], t1 = (product.max[a] - q[a]) / d[a];
      if (t0 > t1) std::swap(t0, t1);
      near = std::max(near, t0);
      far = std::min(far, t1);
    }
    return near <= far;
  };
  // Every patch with a point in the box's shadow — its corners and a 9 x 9 grid of points
  // over each triangle — is listed for that light; and the walk lists few others: the
  // product's bounding sphere swept, the test before the prism, reaches more (here 70 pairs
  // by these points alone, against 55 listed, 37 of them in the shadow; the prism is widened
  // by what the filtered map can darken).
  size_t inside = 0, sphereSwept = 0, listedPairs = 0;
  const glm::dvec3 centre = product.centre();
  const double radius = 0.5 * glm::length(product.size());
  for (uint32_t patch : b.sets.receivers) {
    for (size_t k = 0; k < towards.size(); ++k) {
      bool shadowed = false, nearSphere = false;
      for (uint32_t t = mesh.patches[patch].firstTriangle;
           t < mesh.patches[patch].firstTriangle + 2; ++t) {
        const glm::dvec3 a = mesh.positions[mesh.indices[3 * t]];
        const glm::dvec3 e1 = mesh.positions[mesh.indices[3 * t + 1]] - a;
        const glm::dvec3 e2 = mesh.positions[mesh.indices[3 * t + 2]] - a;
        for (int i = 0; i <= 8; ++i) {
          for (int j = 0; i + j <= 8; ++j) {
            const glm::dvec3 q = a + (i / 8.0) * e1 + (j / 8.0) * e2;
            shadowed = shadowed || inShadow(q, towards[k]);
            const double along = glm::dot(q - centre, towards[k]);
            nearSphere = nearSphere || (along <= radius &&
                                        glm::length(q - centre - along * towards[k]) <= radius);
          }
        }
      }
      sphereSwept += nearSphere;
      listedPairs += listed(k, patch);
      if (!shadowed) continue;
      ++inside;
      EXPECT_TRUE(listed(k, patch)) << "patch " << patch << " light " << k;
    }
  }
  EXPECT_GT(inside, 10u);
  EXPECT_LT(listedPairs, sphereSwept) << "listed " << listedPairs << ", in the shadow " << inside;
  EXPECT_LT(stage.distinctPatches(), b.sets.receivers.size() / 2) << "the walk culls";

  // Shares: a receiver vertex sees light k with E_k = power_k max(0, n.l_k) V_k, V_k the
  // room's own visibility of the light (static_room_visibility.h).
  const VertexS s = stage.s();
  ASSERT_EQ(s.clusters, 3u);
  size_t checked = 0;
  for (uint32_t rv : stage.frameVertices()) {
    const glm::dvec3& n = mesh.normals[b.transfers.receiverVertices[rv]];
    glm::dvec3 e[3], total(0.0);
    for (size_t k = 0; k < 3; ++k) {
      const double seen =
          stage.roomVisibility().visibility(rv, StaticRoomVisibility::lookup(towards[k]));
      e[k] = power[k] * (std::max(0.0, glm::dot(n, towards[k])) * seen);
      total += e[k];
    }
    for (size_t k = 0; k < 3; ++k) {
      const core::Rgb16 got = s.receiverS[size_t(s.vertexSlot[rv]) * 3 + k];
      EXPECT_NEAR(got.r, total.x > 0 ? 65280.0 * e[k].x / total.x : 0.0, 0.5);
      EXPECT_NEAR(got.b, total.z > 0 ? 65280.0 * e[k].z / total.z : 0.0, 0.5);
    }
    ++checked;
  }
  EXPECT_GT(checked, 20u);
  EXPECT_THROW(stage.compute({towards, std::span(power).first(2)}, product, 2, {}),
               std::invalid_argument);
}

// The whole frame: an overhead light puts the shadow under the product; a light from +x moves
// it towards -x; the product is lit from the side that faces the light; bytes do not depend
// on the thread count.
TEST(EnvironmentLightFrame, ShadowsFollowTheLightsAndBytesDoNotDependOnThreads) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop one(b, 256, {}), two(b, 256, {simd::Isa::kScalar, 2, 32});
  const envmap::LightSet none;
  one.step(b.startPose, none);
  const std::vector<uint8_t> productOnly = one.rgba;
  EXPECT_EQ(one.stats.passes, 0u);

  const envmap::LightSet above = {light(1, {0, 1, 0}, 0.6)};
  one.step(b.startPose, above);
  const Changed under = shadowPixels(b, one.rgba, productOnly);
  EXPECT_EQ(one.stats.passes, 1u);
  EXPECT_GT(under.count, 200u);

  const envmap::LightSet fromPlusX = {light(1, {1, 0.5, 0}, 0.6)};
  one.step(b.startPose, fromPlusX);
  const Changed moved = shadowPixels(b, one.rgba, productOnly);
  two.step(b.startPose, fromPlusX);
  EXPECT_EQ(one.rgba, two.rgba) << "1 and 2 threads";
  EXPECT_GT(moved.count, under.count) << "a lower light casts a longer shadow";
  // The camera looks along (2.85, -0.9, 2.45): its right is (-2.45, 0, 2.85), so a shadow
  // pushed towards -x moves right in the image.
  EXPECT_GT(moved.meanColumn, under.meanColumn + 5.0);

  // Many lights, one pass each; the same lights give the same bytes again (no state leaks).
  envmap::LightSet many;
  for (uint32_t i = 0; i < 24; ++i) {
    many.push_back(light(i + 1, {std::cos(0.26 * i), 0.3 + 0.05 * i, std::sin(0.26 * i)}, 0.05));
  }
  one.step(b.startPose, many);
  EXPECT_EQ(one.stats.passes, 24u);
  const std::vector<uint8_t> first = one.rgba;
  one.step(b.startPose, above);
  one.step(b.startPose, many);
  EXPECT_EQ(one.rgba, first);
  two.step(b.startPose, many);
  EXPECT_EQ(two.rgba, first);

  CompositorOptions u8;
  u8.accumulation = raster::Accumulation::kU8;
  FrameLoop graded(b, u8, {});
  EXPECT_THROW(graded.step(b.startPose, above), std::invalid_argument);
}

// The room's own occlusion in the frame: the teapot (0.25 m tall) on the floor in front of
// the desk, a low light (14 degrees) from +z behind the desk. The floor the teapot's shadow
// falls on is already in the desk's shadow of that light — the photograph holds it — so the
// product takes nothing more there; two metres to the side, where the desk is not in the
// way, the same light and product cast a shadow.
TEST(EnvironmentLightFrame, TheDeskHidesTheLightItShadowsAlready) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  const envmap::LightSet behindTheDesk = {light(1, {0, 0.25, 1}, 0.6)};
  const auto shadowAt = [&](float x) {
    const ProductPose pose{2, x, 3.2f, 0, 0};
    loop.step(pose, envmap::LightSet{});
    const std::vector<uint8_t> productOnly = loop.rgba;
    size_t product = 0;
    for (size_t i = 0; i < productOnly.size(); ++i) product += productOnly[i] != b.background[i];
    EXPECT_GT(product, 300u) << "the teapot is in view at x " << x;
    loop.step(pose, behindTheDesk);
    return shadowPixels(b, loop.rgba, productOnly).count;
  };
  EXPECT_EQ(shadowAt(5.1f), 0u) << "in front of the desk";
  EXPECT_GT(shadowAt(3.1f), 100u) << "in the open";
}

TEST(EnvironmentLightFrame, TheProductIsLitOnTheSideFacingTheLight) {
  const SceneBundle& b = testing::showroomBundle();
  FrameLoop loop(b, 256, {});
  const auto meanRedFacing = [&](double towardsX) {
    loop.step(b.startPose, envmap::LightSet{light(1, {towardsX, 0.2, 0}, 1.0)});
    const raster::ShadedMesh& product = loop.frame.objects[0];
    const std::vector<glm::vec3> normals =
        shadingNormals(b.products[b.startPose.product], product.mesh, b.startPose);
    double sum = 0;
    size_t count = 0;
    for (size_t v = 0; v < normals.size(); ++v) {
      if (glm::normalize(glm::dvec3(normals[v])).x < 0.7) continue;  // faces +x
      sum += product.colours[v].r;
      ++count;
    }
    EXPECT_GT(count, 0u);
    return sum / double(count);
  };
  const double lit = meanRedFacing(1.0), away = meanRedFacing(-1.0);
  EXPECT_GT(lit, away + 20.0) << "faces +x: lit by a light at +x, dark under one at -x";
}

}  // namespace
}  // namespace penumbra::shadow

namespace penumbra::shadow {
namespace {

// Havran 2005 §4.2: a glossy highlight from many faint lights beside the mirror direction is
// dimmer than from their cluster, which sits in the middle of them, right on it; with fine
// lights equal to the frame's lights the two strata give the frame's lights' colour.
TEST(EnvironmentLightShading, GlossyStrataTakeTheFineLightsInsideTheLobesCone) {
  SceneBundle b = testing::showroomBundle();
  b.products[0].specular = glm::vec3(0.6f);
  b.products[0].specularExponent = 60.0f;
  b.products[0].reflectances.clear();
  b.products[0].reflectance = glm::vec3(0.05f);
  const scene::PatchMesh mesh = patchMeshOf(b);
  ProductShading shading(b, mesh, scene::Aabb{{0, 0, 0}, {6, 3, 5}}, {});
  core::Mesh tile;
  tile.positions = {{3.0f, 0.5f, 2.4f}, {3.1f, 0.5f, 2.4f}, {3.0f, 0.5f, 2.5f}};
  tile.indices = {0, 1, 2};
  const std::vector<glm::vec3> normals(3, glm::vec3(0, 1, 0));
  // The mirror direction of the kiosk camera (eye (0.35, 1.6, 0.35)) about +y at vertex 0.
  const glm::dvec3 toEye = glm::normalize(glm::dvec3(0.35, 1.6, 0.35) - glm::dvec3(3.0, 0.5, 2.4));
  const glm::dvec3 mirror = 2.0 * toEye.y * glm::dvec3(0, 1, 0) - toEye;
  // Two fine lights 12° either side of it (turned about the axis across it in the xz plane).
  const glm::dvec3 across = glm::normalize(glm::cross(mirror, glm::dvec3(0, 1, 0)));
  const double c = std::cos(12.0 * std::numbers::pi / 180),
               s = std::sin(12.0 * std::numbers::pi / 180);
  const std::vector<glm::dvec3> fine = {c * mirror + s * across, c * mirror - s * across};
  const std::vector<glm::dvec3> finePower(2, glm::dvec3(0.01));
  const std::vector<glm::dvec3> cluster = {glm::normalize(fine[0] + fine[1])};
  const std::vector<glm::dvec3> clusterPower = {glm::dvec3(0.02)};

  shading.shadeFromLights(tile, normals, 0, cluster, clusterPower);
  const core::Rgb8 coarse = shading.colours()[0];
  const glm::dvec3 coarseRadiance = shading.radiance()[0];
  shading.shadeFromLights(tile, normals, 0, cluster, clusterPower, fine, finePower);
  const core::Rgb8 strata = shading.colours()[0];
  EXPECT_EQ(shading.radiance()[0], coarseRadiance) << "the passes' shares keep the clusters";
  EXPECT_LT(int(strata.r) + 20, int(coarse.r)) << "the peak of the lobe is not where the light is";
  shading.shadeFromLights(tile, normals, 0, cluster, clusterPower, cluster, clusterPower);
  EXPECT_EQ(shading.colours()[0], coarse) << "fine lights = the clusters: the same colour";
  EXPECT_THROW(shading.shadeFromLights(tile, normals, 0, cluster, clusterPower, fine,
                                       std::span(finePower).first(1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
