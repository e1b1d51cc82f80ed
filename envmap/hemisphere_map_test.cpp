#include "envmap/hemisphere_map.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "envmap/envmap_test_util.h"

namespace penumbra::envmap {
namespace {

using testutil::angleDegrees;

TEST(HemisphereMap, ConcentricMapCornersAndCentre) {
  EXPECT_EQ(concentricSquareToDisk(0.5, 0.5).u, 0.0);
  const DiskPolar right = concentricSquareToDisk(1.0, 0.5);
  EXPECT_EQ(right.u, 1.0);
  EXPECT_EQ(right.turns, 0.0);
  EXPECT_EQ(concentricSquareToDisk(1.0, 1.0).turns, 0.125);  // corner: 45°
  EXPECT_EQ(concentricSquareToDisk(0.5, 1.0).turns, 0.25);
  EXPECT_EQ(concentricSquareToDisk(0.0, 0.5).turns, 0.5);
  EXPECT_EQ(concentricSquareToDisk(0.5, 0.0).turns, 0.75);
  EXPECT_EQ(concentricSquareToDisk(0.75, 0.5).u, 0.25);  // r = 0.5
}

// Havran 2005 §3.1, Fig. 2: the square → hemisphere map has no seam at azimuth 0 and none at
// the wedges' diagonals: a step of 1e-6 in the square moves the direction by well under 0.01°.
TEST(HemisphereMap, SquareToHemisphereIsContinuousAcrossSeams) {
  const double eps = 1e-6;
  const std::array<std::array<double, 2>, 5> seams = {
      {{0.9, 0.5}, {0.8, 0.8}, {0.2, 0.8}, {0.2, 0.2}, {0.8, 0.2}}};
  for (const auto& p : seams) {
    for (int axis = 0; axis < 2; ++axis) {
      const double s0 = p[0] - (axis == 0 ? eps : 0), t0 = p[1] - (axis == 1 ? eps : 0);
      const double s1 = p[0] + (axis == 0 ? eps : 0), t1 = p[1] + (axis == 1 ? eps : 0);
      const glm::dvec3 a = diskToHemisphere(concentricSquareToDisk(s0, t0));
      const glm::dvec3 b = diskToHemisphere(concentricSquareToDisk(s1, t1));
      EXPECT_LT(angleDegrees(a, b), 0.01) << "at (" << p[0] << ", " << p[1] << ") axis " << axis;
    }
  }
}

// Area preservation: a uniform grid over the square lands uniformly in solid angle, so each of
// four bands of equal height in z (equal solid angle) and each of four azimuth quadrants gets
// a quarter of the points, up to the grid's staircase along the bands' square outlines (1.2%
// here). A map with z = 1 − r instead of 1 − r² would put 44% in the top band.
TEST(HemisphereMap, SquareToHemispherePreservesArea) {
  const int n = 400;
  std::array<int, 4> bands{}, quadrants{};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const glm::dvec3 d = diskToHemisphere(concentricSquareToDisk((i + 0.5) / n, (j + 0.5) / n));
      EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
      ++bands[std::min(3, int(d.z * 4))];
      ++quadrants[(d.x >= 0 ? 0 : 1) + (d.y >= 0 ? 0 : 2)];
    }
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(bands[k], n * n / 4, n * n / 250) << "z band " << k;
    EXPECT_NEAR(quadrants[k], n * n / 4, n * n / 250) << "quadrant " << k;
  }
}

TEST(HemisphereMap, PixelsCoverTheHemisphereWithEqualSolidAngle) {
  const HemisphereMap map = testutil::uniformMap({1, 1, 1});
  EXPECT_NEAR(map.pixelSolidAngle() * map.rows() * map.cols(), 2 * 3.14159265358979323846, 1e-12);
  // Row 0 is at the zenith, the last row at the horizon; column 90 of 360 faces +y.
  EXPECT_GT(map.pixelCentre(0, 0).z, 0.99);
  EXPECT_LT(map.pixelCentre(0, map.rows() - 1).z, 0.01);
  const glm::dvec3 d = map.pixelCentre(90, 45);
  EXPECT_GT(d.y, 0.8);
  EXPECT_NEAR(d.z, 1.0 - 45.5 / 90, 1e-12);
}

}  // namespace
}  // namespace penumbra::envmap
