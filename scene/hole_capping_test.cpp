// Capping a solid product's proxy: every boundary loop closed with consistent winding, and
// the boundaries that are not simple loops refused with the mesh unchanged.
#include "scene/hole_capping.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <utility>

namespace penumbra::scene {
namespace {

// A unit cube wound counter-clockwise from outside, optionally without some of its six
// faces (two triangles each).
TriangleMesh cube(std::initializer_list<int> missing = {}) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.positions.push_back({i & 1, (i >> 1) & 1, (i >> 2) & 1});
  const uint32_t faces[6][6] = {{0, 2, 3, 0, 3, 1}, {4, 5, 7, 4, 7, 6}, {0, 1, 5, 0, 5, 4},
                                {2, 6, 7, 2, 7, 3}, {0, 4, 6, 0, 6, 2}, {1, 3, 7, 1, 7, 5}};
  for (int f = 0; f < 6; ++f) {
    if (std::find(missing.begin(), missing.end(), f) != missing.end()) continue;
    m.indices.insert(m.indices.end(), faces[f], faces[f] + 6);
  }
  return m;
}

// Every directed edge once, its reverse once: closed and consistently wound.
bool closed(const TriangleMesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    for (int i = 0; i < 3; ++i) ++edges[{m.indices[t + i], m.indices[t + (i + 1) % 3]}];
  }
  for (const auto& [e, n] : edges) {
    const auto reverse = edges.find({e.second, e.first});
    if (n != 1 || reverse == edges.end() || reverse->second != 1) return false;
  }
  return true;
}

double signedVolume(const TriangleMesh& m) {
  double v = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const glm::dvec3 &a = m.positions[m.indices[t]], &b = m.positions[m.indices[t + 1]],
                     &c = m.positions[m.indices[t + 2]];
    v += glm::dot(a, glm::cross(b, c)) / 6;
  }
  return v;
}

TEST(HoleCapping, EveryLoopIsClosedWithTheSurfacesWinding) {
  TriangleMesh closedCube = cube();
  EXPECT_EQ(capHoles(closedCube), 0u);
  EXPECT_EQ(closedCube.indices, cube().indices);

  // Top and bottom open (a tube): two square loops, each capped by four triangles about
  // its centre; the cube's volume comes back exactly (the caps are flat).
  TriangleMesh tube = cube({2, 3});
  tube.normals.assign(8, {0, 0, 1});
  ASSERT_FALSE(closed(tube));
  EXPECT_EQ(capHoles(tube), 2u);
  EXPECT_TRUE(closed(tube));
  EXPECT_EQ(tube.positions.size(), 10u);
  EXPECT_EQ(tube.triangleCount(), 8u + 8u);
  EXPECT_DOUBLE_EQ(signedVolume(tube), 1.0);
  EXPECT_EQ(tube.positions[8], glm::dvec3(0.5, 0, 0.5));  // the y = 0 loop's centre
  EXPECT_TRUE(tube.normals.empty());

  // Two faces that share an edge open: one loop of six edges.
  TriangleMesh corner = cube({1, 3});
  EXPECT_EQ(capHoles(corner), 1u);
  EXPECT_TRUE(closed(corner));
  EXPECT_GT(signedVolume(corner), 0.0);
}

TEST(HoleCapping, BoundariesThatAreNotSimpleLoopsAreLeftAlone) {
  // Two triangles meeting at vertex 0 only (a bowtie): 0 starts two boundary edges.
  TriangleMesh bowtie;
  bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  bowtie.indices = {0, 1, 2, 0, 3, 4};
  const TriangleMesh pinched = bowtie;
  EXPECT_EQ(capHoles(bowtie), std::nullopt);
  EXPECT_EQ(bowtie.indices, pinched.indices);
  EXPECT_EQ(bowtie.positions, pinched.positions);

  TriangleMesh doubled = cube();
  doubled.indices.insert(doubled.indices.end(), {0, 2, 3});  // 0 -> 2 used twice
  const TriangleMesh unchanged = doubled;
  EXPECT_EQ(capHoles(doubled), std::nullopt);
  EXPECT_EQ(doubled.indices, unchanged.indices);
  EXPECT_EQ(doubled.positions, unchanged.positions);
}

}  // namespace
}  // namespace penumbra::scene
