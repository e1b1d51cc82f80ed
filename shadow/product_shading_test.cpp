// Product shading without an irradiance volume: every emitter's form-factor transfer summed
// into the vertex radiance, through T(); the source set's transfers kept per source for
// self-shadowing (Gibson 2003 §7.2).
#include "shadow/product_shading.h"

#include <gtest/gtest.h>

#include <utility>

namespace penumbra::shadow {
namespace {

scene::Patch lamp(glm::dvec3 centre, glm::dvec3 emission) {
  scene::Patch p;
  p.centre = centre;
  p.normal = {0, -1, 0};
  p.area = 0.25;
  p.emission = emission;
  return p;
}

struct LampRoom {
  LampRoom() {
    // Patch 0: an emitter in the source set; 1: an emitter left out of it; 2: a wall.
    mesh.patches = {lamp({0.3, 2.0, 0.3}, {4, 4, 4}), lamp({0.5, 2.5, -0.5}, {2, 1, 0.5}),
                    lamp({0, 1, 0}, {0, 0, 0})};
    bundle.tone = ToneCurve::gamma(1.0);
    bundle.sets.sources = {0};
    ProductModel m;
    m.reflectance = {0.5f, 0.25f, 1.0f};
    bundle.products = {m};
    bundle.view.cameraViewProj = core::Mat4::identity();
  }
  SceneBundle bundle;
  scene::PatchMesh mesh;
};

TEST(ProductShading, EmittersLightTheVerticesAndSourcesKeepTheirTransfers) {
  const LampRoom room;
  ProductShading shading(room.bundle, room.mesh, scene::Aabb{{-2, 0, -2}, {2, 3, 2}}, {});
  // One triangle facing +y (cross product of length 1: the normal is exactly (0, 1, 0)).
  core::Mesh placed;
  placed.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
  placed.indices = {0, 1, 2};
  scene::Aabb bounds = scene::Aabb::emptyBox();
  for (const core::Vec3& p : placed.positions) bounds.extend({p.x, p.y, p.z});
  shading.shade(placed, bounds, 0);

  ASSERT_EQ(shading.colours().size(), 3u);
  ASSERT_EQ(shading.sourceTransfers().size(), 3u);  // 1 source x 3 vertices
  const glm::dvec3 reflectance(room.bundle.products[0].reflectance);
  const glm::dvec3 up(0, 1, 0);
  for (size_t v = 0; v < 3; ++v) {
    const glm::dvec3 x(placed.positions[v].x, placed.positions[v].y, placed.positions[v].z);
    glm::dvec3 expected(0.0), fromSource(0.0);
    for (size_t p = 0; p < 2; ++p) {
      const scene::Patch& e = room.mesh.patches[p];
      const glm::dvec3 t = reflectance * e.emission *
                           scene::pointToPatchFormFactor(x, up, e.centre, e.normal, e.area);
      expected += t;
      if (p == 0) fromSource = t;
    }
    EXPECT_GT(fromSource.x, 0.0);
    EXPECT_EQ(shading.radiance()[v], expected) << "vertex " << v;
    EXPECT_EQ(shading.sourceTransfers()[v], fromSource) << "vertex " << v;
    EXPECT_EQ(shading.colours()[v], room.bundle.tone.map(expected)) << "vertex " << v;
  }
}

TEST(ProductShading, ShadingFollowsTheLastPlacement) {
  const LampRoom room;
  ProductShading shading(room.bundle, room.mesh, scene::Aabb{{-2, 0, -2}, {2, 3, 2}}, {});
  core::Mesh placed;
  placed.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
  placed.indices = {0, 1, 2};
  shading.shade(placed, scene::Aabb{{0, 0, 0}, {1, 0, 1}}, 0);
  const glm::dvec3 near = shading.radiance()[0];
  for (core::Vec3& p : placed.positions) p.y -= 1.0f;  // a metre further from the lamps
  shading.shade(placed, scene::Aabb{{0, -1, 0}, {1, -1, 1}}, 0);
  EXPECT_LT(shading.radiance()[0].x, near.x);
  // Facing away from every lamp: no light, T(0).
  std::swap(placed.indices[1], placed.indices[2]);
  shading.shade(placed, scene::Aabb{{0, -1, 0}, {1, -1, 1}}, 0);
  EXPECT_EQ(shading.radiance()[0], glm::dvec3(0.0));
  EXPECT_EQ(shading.colours()[0], room.bundle.tone.map(glm::dvec3(0.0)));
}

}  // namespace
}  // namespace penumbra::shadow
