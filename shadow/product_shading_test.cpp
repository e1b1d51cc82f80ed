// Product shading without an irradiance volume: every emitter's form-factor transfer summed
// into the vertex radiance, through T(); the source set's transfers kept per source for
// self-shadowing (Gibson 2003 §7.2).
#include "shadow/product_shading.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>
#include <utility>

#include "scene/mesh_io.h"
#include "shadow/product_placement.h"

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

// A box product shaded from a one-vertex irradiance volume (E depends on the normal only:
// the trilinear blend of a single record is that record), placed at 30 degrees.
struct BoxRoom : LampRoom {
  BoxRoom() {
    bundle.irradiance.dims = {1, 1, 1};
    for (size_t i = 0; i < kShFloats; ++i) {
      bundle.irradiance.coefficients.push_back(0.3f + 0.05f * float(i % 9));
    }
    bundle.irradiance.valid = {1};
    const scene::TriangleMesh box = scene::parseObj(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n",
        "box.obj");
    ProductModel& m = bundle.products[0];
    for (const glm::dvec3& p : box.positions) m.mesh.positions.push_back(scene::toVec3(p));
    m.mesh.indices = box.indices;
    for (const glm::dvec3& n : box.normals) m.normals.push_back(glm::vec3(n));
  }
};

// Issue 15 item 6: "a box OBJ with shared corners is shaded with averaged normals, so its
// faces show bands". With the model's flat normals every face is one colour; the old
// area-weighted normals of the welded box shade a face's corners differently.
TEST(ProductShading, FlatShadedBoxShadesEachFaceUniformly) {
  const BoxRoom room;
  ProductPlacement placement(room.bundle.products);
  placement.place({0, 1.0f, 0.5f, 30.0f, 0.0f});
  ProductShading shading(room.bundle, room.mesh, scene::Aabb{{-2, 0, -2}, {2, 3, 2}}, {});
  shading.shade(placement.mesh(), placement.normals(), placement.bounds(), 0);
  const core::Mesh& m = placement.mesh();
  ASSERT_EQ(m.positions.size(), 24u);
  std::set<std::tuple<int, int, int>> faceColours;
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    const core::Rgb8 c = shading.colours()[m.indices[3 * t]];
    for (int k = 1; k < 3; ++k) {
      EXPECT_EQ(shading.colours()[m.indices[3 * t + size_t(k)]], c) << "triangle " << t;
      EXPECT_EQ(placement.normals()[m.indices[3 * t + size_t(k)]],
                placement.normals()[m.indices[3 * t]]);
    }
    faceColours.insert({c.r, c.g, c.b});
  }
  EXPECT_GE(faceColours.size(), 3u);  // the faces differ from one another

  // The same box welded to its 8 corners (what the loader made before), area-weighted:
  // some face is shaded in bands.
  core::Mesh welded;
  welded.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                      {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  welded.indices = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                    3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
  ProductShading old(room.bundle, room.mesh, scene::Aabb{{-2, 0, -2}, {2, 3, 2}}, {});
  old.shade(welded, scene::Aabb{{0, 0, 0}, {1, 1, 1}}, 0);
  size_t banded = 0;
  for (size_t t = 0; t < welded.triangleCount(); ++t) {
    const core::Rgb8 c = old.colours()[welded.indices[3 * t]];
    if (!(old.colours()[welded.indices[3 * t + 1]] == c) ||
        !(old.colours()[welded.indices[3 * t + 2]] == c)) {
      ++banded;
    }
  }
  EXPECT_GT(banded, 0u);
}

// Per-vertex reflectances replace the product's one reflectance in the volume path and the
// emitter path.
TEST(ProductShading, PerVertexReflectancesColourTheirVertices) {
  BoxRoom room;
  ProductModel& m = room.bundle.products[0];
  for (size_t v = 0; v < m.mesh.positions.size(); ++v) {
    m.reflectances.push_back(v % 2 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1));
  }
  ProductPlacement placement(room.bundle.products);
  placement.place({0, 1.0f, 0.5f, 0.0f, 0.0f});
  for (const bool volume : {true, false}) {
    ProductShadingOptions options;
    options.shadeFromVolume = volume;
    ProductShading shading(room.bundle, room.mesh, scene::Aabb{{-2, 0, -2}, {2, 3, 2}}, options);
    shading.shade(placement.mesh(), placement.normals(), placement.bounds(), 0);
    for (size_t v = 0; v < m.mesh.positions.size(); ++v) {
      const glm::dvec3 l = shading.radiance()[v];
      EXPECT_EQ(l.y, 0.0) << v;
      EXPECT_EQ(v % 2 ? l.z : l.x, 0.0) << v;
    }
  }
  // A placed mesh that is not the model's, with per-vertex reflectances: refused.
  ProductShading shading(room.bundle, room.mesh, scene::Aabb{{-2, 0, -2}, {2, 3, 2}}, {});
  core::Mesh other;
  other.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
  other.indices = {0, 1, 2};
  EXPECT_THROW(shading.shade(other, scene::Aabb{{0, 0, 0}, {1, 0, 1}}, 0), std::invalid_argument);
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
