// Closed outward surfaces: what may be drawn into shadow maps front faces only.
#include "raster/closed_surface.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace penumbra::raster {
namespace {

// A unit cube at `x`, its 12 triangles wound counter-clockwise seen from outside.
core::Mesh cube(float x = 0) {
  core::Mesh m;
  for (int i = 0; i < 8; ++i) {
    m.positions.push_back({x + float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
  }
  m.indices = {0, 2, 3, 0, 3, 1,   // z = 0, normal -z
               4, 5, 7, 4, 7, 6,   // z = 1, +z
               0, 1, 5, 0, 5, 4,   // y = 0, -y
               2, 6, 7, 2, 7, 3,   // y = 1, +y
               0, 4, 6, 0, 6, 2,   // x = 0, -x
               1, 3, 7, 1, 7, 5};  // x = 1, +x
  return m;
}

core::Mesh join(core::Mesh a, const core::Mesh& b) {
  const auto base = static_cast<uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t i : b.indices) a.indices.push_back(base + i);
  return a;
}

core::Mesh flipped(core::Mesh m) {
  for (size_t t = 0; t < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
  return m;
}

TEST(ClosedSurface, AClosedOutwardCubeIsOneAndEveryFaultIsCaught) {
  EXPECT_TRUE(isClosedOutwardSurface(cube()));
  EXPECT_TRUE(isClosedOutwardSurface(join(cube(), cube(3))));  // two pieces
  EXPECT_FALSE(isClosedOutwardSurface(flipped(cube())));       // wound inward
  // One piece inward: the total volume is 0, and each piece is checked anyway.
  EXPECT_FALSE(isClosedOutwardSurface(join(cube(), flipped(cube(3)))));
  // A big outward cube around a small inward one: total positive, one piece negative.
  core::Mesh big = cube();
  for (core::Vec3& p : big.positions) p = {3 * p.x - 1, 3 * p.y - 1, 3 * p.z - 1};
  EXPECT_FALSE(isClosedOutwardSurface(join(big, flipped(cube()))));

  core::Mesh open = cube();
  open.indices.resize(open.indices.size() - 3);  // a hole
  EXPECT_FALSE(isClosedOutwardSurface(open));
  core::Mesh inconsistent = cube();
  std::swap(inconsistent.indices[1], inconsistent.indices[2]);  // one triangle flipped
  EXPECT_FALSE(isClosedOutwardSurface(inconsistent));
  core::Mesh doubled = cube();
  doubled.indices.insert(doubled.indices.end(), {0, 2, 3, 3, 2, 0});  // a fin: edges used twice
  EXPECT_FALSE(isClosedOutwardSurface(doubled));
  core::Mesh degenerate = cube();
  degenerate.indices.insert(degenerate.indices.end(), {0, 0, 1});
  EXPECT_FALSE(isClosedOutwardSurface(degenerate));
  core::Mesh seam = cube();  // vertex 0 split for the -z face: the same place, open by index
  seam.positions.push_back(seam.positions[0]);
  seam.indices[0] = seam.indices[3] = 8;
  EXPECT_FALSE(isClosedOutwardSurface(seam));
  core::Mesh outOfRange = cube();
  outOfRange.indices[0] = 99;
  EXPECT_FALSE(isClosedOutwardSurface(outOfRange));
  EXPECT_FALSE(isClosedOutwardSurface(core::Mesh{}));
}

}  // namespace
}  // namespace penumbra::raster
