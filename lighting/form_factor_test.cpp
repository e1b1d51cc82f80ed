#include "lighting/form_factor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace penumbra::lighting {
namespace {

using glm::dvec3;
constexpr double kPi = std::numbers::pi;

// Differential area under one corner of an a x b rectangle in a parallel plane at height
// h (Howell's catalogue, configuration B-3).
double parallelCornerFormFactor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

// Differential area whose plane is perpendicular to a w x h rectangle, on the normal of
// the rectangle through one corner of its edge in the element's plane, at distance c
// (Howell's catalogue, configuration B-2).
double perpendicularCornerFormFactor(double w, double h, double c) {
  const double x = h / w, y = c / w, r = std::sqrt(x * x + y * y);
  return (std::atan(1 / y) - y / r * std::atan(1 / r)) / (2 * kPi);
}

// The edge sum of pointToPolygonFormFactor without the clip, as a reference for what the
// clip changes.
double unclippedContourIntegral(const dvec3& x, const dvec3& n, const std::vector<dvec3>& poly) {
  double sum = 0;
  for (size_t k = 0; k < poly.size(); ++k) {
    const dvec3 r0 = poly[k] - x, r1 = poly[(k + 1) % poly.size()] - x;
    const dvec3 c = glm::cross(r0, r1);
    sum += std::atan2(glm::length(c), glm::dot(r0, r1)) * glm::dot(n, c) / glm::length(c);
  }
  return std::abs(sum) / (2 * kPi);
}

std::vector<dvec3> rectangle(const dvec3& origin, const dvec3& u, const dvec3& v) {
  return {origin, origin + u, origin + u + v, origin + v};
}

TEST(FormFactor, ParallelSquareCentredAbove) {
  const double side = 1.4, h = 0.9;
  const auto square =
      rectangle(dvec3(-side / 2, -side / 2, h), dvec3(side, 0, 0), dvec3(0, side, 0));
  // By symmetry the centred square is four corner rectangles.
  const double expected = 4 * parallelCornerFormFactor(side / 2, side / 2, h);
  EXPECT_NEAR(pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), square), expected, 1e-12);
}

TEST(FormFactor, WindingDoesNotMatter) {
  auto square = rectangle(dvec3(0.3, -0.2, 1.1), dvec3(0.8, 0, 0), dvec3(0, 0.5, 0));
  const double f = pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), square);
  std::reverse(square.begin(), square.end());
  EXPECT_DOUBLE_EQ(pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), square), f);
  EXPECT_NEAR(f,
              parallelCornerFormFactor(1.1, 0.3, 1.1) - parallelCornerFormFactor(0.3, 0.3, 1.1) +
                  parallelCornerFormFactor(1.1, 0.2, 1.1) - parallelCornerFormFactor(0.3, 0.2, 1.1),
              1e-12);
}

TEST(FormFactor, PerpendicularRectangle) {
  // Element at the origin facing +z; rectangle in the plane y = c, x in [0, w], z in [0, h].
  const double w = 0.8, h = 1.3, c = 0.6;
  const auto rect = rectangle(dvec3(0, c, 0), dvec3(w, 0, 0), dvec3(0, 0, h));
  EXPECT_NEAR(pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), rect),
              perpendicularCornerFormFactor(w, h, c), 1e-12);
}

TEST(FormFactor, FarFieldApproachesPointFormula) {
  // A 1 cm square 3 m away, tilted: cos_i cos_j A / (pi r^2) within 0.01%.
  const dvec3 x(0.1, -0.2, 0.3), n = glm::normalize(dvec3(0.2, 0.1, 1));
  const dvec3 centre(0.8, 0.4, 3.2);
  const dvec3 u = 0.01 * glm::normalize(dvec3(1, 0, 0.3));
  const dvec3 v = 0.01 * glm::normalize(glm::cross(dvec3(-0.3, 0.1, -1), u));
  const auto square = rectangle(centre - 0.5 * u - 0.5 * v, u, v);
  const dvec3 d = centre - x;
  const double r = glm::length(d);
  const dvec3 m = glm::normalize(glm::cross(u, v));
  const double expected = glm::dot(n, d) / r * std::abs(glm::dot(m, d)) / r *
                          glm::length(glm::cross(u, v)) / (kPi * r * r);
  EXPECT_NEAR(pointToPolygonFormFactor(x, n, square) / expected, 1.0, 1e-4);
}

TEST(FormFactor, PolygonBehindReceiverIsZero) {
  const auto below = rectangle(dvec3(-1, -1, -0.5), dvec3(2, 0, 0), dvec3(0, 2, 0));
  EXPECT_EQ(pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), below), 0.0);
  // In the receiver's own plane: no projected solid angle.
  const auto coplanar = rectangle(dvec3(1, -1, 0), dvec3(2, 0, 0), dvec3(0, 2, 0));
  EXPECT_EQ(pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), coplanar), 0.0);
  EXPECT_EQ(pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), std::vector<dvec3>{}), 0.0);
}

TEST(FormFactor, PartlyBehindIsClippedToTheHemisphere) {
  // A wall in the plane y = c crossing the receiver's tangent plane z = 0: only its upper
  // part counts, which is the perpendicular configuration again.
  const double w = 0.8, h = 1.3, c = 0.6;
  const auto crossing = rectangle(dvec3(0, c, -0.7), dvec3(w, 0, 0), dvec3(0, 0, h + 0.7));
  const double f = pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), crossing);
  EXPECT_NEAR(f, perpendicularCornerFormFactor(w, h, c), 1e-12);
  EXPECT_GT(f, 0.0);
  // Bounded by the same wall moved wholly into the hemisphere...
  const auto lifted = rectangle(dvec3(0, c, 0), dvec3(w, 0, 0), dvec3(0, 0, h + 0.7));
  EXPECT_LT(f, pointToPolygonFormFactor(dvec3(0), dvec3(0, 0, 1), lifted));
  // ...and not what the unclipped contour integral gives: that counts the part below the
  // horizon with a negative cosine and comes out smaller.
  EXPECT_LT(unclippedContourIntegral(dvec3(0), dvec3(0, 0, 1), crossing), f - 1e-3);
}

TEST(FormFactor, ClosedBoxSumsToOne) {
  // From any point on a face of a closed box, the other five faces fill the hemisphere.
  const dvec3 lo(0), hi(2.0, 1.5, 3.0);
  const dvec3 x(0.7, 1.5, 1.1), n(0, -1, 0);  // on the ceiling, facing down
  const std::vector<std::vector<dvec3>> faces = {
      rectangle(lo, dvec3(hi.x, 0, 0), dvec3(0, 0, hi.z)),                 // floor
      rectangle(lo, dvec3(0, hi.y, 0), dvec3(0, 0, hi.z)),                 // x = 0
      rectangle(dvec3(hi.x, 0, 0), dvec3(0, hi.y, 0), dvec3(0, 0, hi.z)),  // x = max
      rectangle(lo, dvec3(hi.x, 0, 0), dvec3(0, hi.y, 0)),                 // z = 0
      rectangle(dvec3(0, 0, hi.z), dvec3(hi.x, 0, 0), dvec3(0, hi.y, 0)),  // z = max
  };
  double sum = 0;
  for (const auto& f : faces) sum += pointToPolygonFormFactor(x, n, f);
  EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST(FormFactor, ClipKeepsOnlyTheFrontPart) {
  const auto square = rectangle(dvec3(-1, -1, -1), dvec3(2, 0, 0), dvec3(0, 0, 2));
  const auto clipped = clipPolygonToHemisphere(dvec3(0), dvec3(0, 0, 1), square);
  ASSERT_EQ(clipped.size(), 4u);
  for (const dvec3& p : clipped) EXPECT_GE(p.z, 0.0);
}

}  // namespace
}  // namespace penumbra::lighting
