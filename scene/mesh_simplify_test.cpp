// Shadow proxies by quadric simplification (meshoptimizer), Gibson 2003 §7.2.
#include "scene/mesh_simplify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <utility>
#include <vector>

#include "scene/mesh_io.h"
#include "tests/test_data.h"

namespace penumbra::scene {
namespace {

namespace fs = std::filesystem;

using penumbra::testing::dataDir;

TEST(MeshSimplify, WeldMergesEqualPositionsAndDropsCollapsedTriangles) {
  TriangleMesh m;
  m.positions = {glm::dvec3(0),       glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0),
                 glm::dvec3(1, 0, 0), glm::dvec3(1, 1, 0), glm::dvec3(5)};
  m.indices = {0, 1, 2, 3, 4, 2, 1, 3, 4};  // the last one collapses after welding
  const TriangleMesh w = weldVertices(m);
  EXPECT_EQ(w.positions.size(), 4u);
  EXPECT_EQ(w.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

// Gibson 2003 §7.2: 100-500 triangle proxies that keep the object's extent, since the
// shadow's reach depends on it. Within 2% from 300 triangles up (the scene default);
// the coarsest proxies may lose a few percent at the tips of the ears.
TEST(MeshSimplify, BunnyProxyKeepsItsBounds) {
  const TriangleMesh bunny = loadMesh(dataDir() / "models" / "bunny.ply");
  for (const auto& [target, tolerance] :
       std::vector<std::pair<size_t, double>>{{100, 0.05}, {300, 0.02}, {500, 0.02}}) {
    const TriangleMesh proxy = simplifyForShadows(bunny, target);
    EXPECT_LE(proxy.triangleCount(), target);
    EXPECT_GE(proxy.triangleCount(), target / 2);
    const Aabb a = bunny.bounds(), b = proxy.bounds();
    const glm::dvec3 size = a.size();
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(a.min[k] - b.min[k]), tolerance * size[k]) << target << " axis " << k;
      EXPECT_LE(std::abs(a.max[k] - b.max[k]), tolerance * size[k]) << target << " axis " << k;
    }
    for (uint32_t i : proxy.indices) ASSERT_LT(i, proxy.positions.size());
  }
}

// A unit sphere of 80 × 40 quads: the simplified proxy on its vertices is inscribed
// (every vertex is on the sphere, every face inside it); the offset proxy is not.
TEST(MeshSimplify, ProxyIsPushedOutToTheModelsMedianSurface) {
  TriangleMesh sphere;
  constexpr int kAround = 80, kUp = 40;
  for (int i = 0; i <= kUp; ++i) {
    const double theta = M_PI * i / kUp;
    for (int j = 0; j < kAround; ++j) {
      const double phi = 2 * M_PI * j / kAround;
      sphere.positions.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta),
                                    std::sin(theta) * std::sin(phi));
    }
  }
  for (int i = 0; i < kUp; ++i) {
    for (int j = 0; j < kAround; ++j) {
      const auto at = [&](int r, int c) {
        return static_cast<uint32_t>(r * kAround + c % kAround);
      };
      // Counter-clockwise seen from outside.
      sphere.indices.insert(sphere.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j),
                                                   at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  const TriangleMesh welded = weldVertices(sphere);
  const TriangleMesh proxy = simplifyForShadows(sphere, 200);
  ASSERT_LE(proxy.triangleCount(), 200u);
  // Every proxy vertex moved out: radii above 1, by less than a proxy edge.
  double smallest = 2, largest = 0;
  for (const glm::dvec3& p : proxy.positions) {
    smallest = std::min(smallest, glm::length(p)), largest = std::max(largest, glm::length(p));
  }
  EXPECT_GT(smallest, 1.0);
  EXPECT_LT(largest, 1.1);
  // Balanced: the median signed distance of the sphere's vertices is now near 0, where the
  // un-moved proxy (all vertices on the sphere, faces inside) left most of them outside.
  EXPECT_LT(std::abs(medianDistanceOutside(welded, proxy)), 0.2 * (largest - 1.0));
  // A proxy sitting on the surface already is left where it is.
  const TriangleMesh small = simplifyForShadows(sphere, 100000);
  EXPECT_EQ(small.positions, welded.positions);
  EXPECT_EQ(medianDistanceOutside(welded, welded), 0.0);
  EXPECT_EQ(medianDistanceOutside(TriangleMesh{}, proxy), 0.0);
}

TEST(MeshSimplify, DeterministicAndWithinTargetForEveryModel) {
  for (const char* name : {"bunny.ply", "teapot.ply", "chair.obj"}) {
    const TriangleMesh m = loadMesh(dataDir() / "models" / name);
    const TriangleMesh a = simplifyForShadows(m, 300), b = simplifyForShadows(m, 300);
    EXPECT_LE(a.triangleCount(), 300u) << name;
    EXPECT_GT(a.triangleCount(), 0u) << name;
    EXPECT_EQ(a.positions, b.positions) << name;
    EXPECT_EQ(a.indices, b.indices) << name;
  }
  EXPECT_THROW(simplifyForShadows(TriangleMesh{}, 3), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::scene
