#include "shadow/light_frustum.h"

#include <gtest/gtest.h>

#include <array>

namespace penumbra::shadow {
namespace {

using glm::dvec3;

std::array<dvec3, 8> corners(const scene::Aabb& b) {
  std::array<dvec3, 8> out{};
  for (int i = 0; i < 8; ++i) {
    out[i] = dvec3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z);
  }
  return out;
}

// The float matrix of the trace, applied as spec §2 does (binary32, left to right).
std::array<float, 4> clipOf(const core::Mat4& m, const dvec3& p) {
  const float x = static_cast<float>(p.x), y = static_cast<float>(p.y), z = static_cast<float>(p.z);
  std::array<float, 4> out{};
  for (int r = 0; r < 4; ++r) {
    out[r] = ((m.m[4 * r] * x + m.m[4 * r + 1] * y) + m.m[4 * r + 2] * z) + m.m[4 * r + 3];
  }
  return out;
}

TEST(LightFrustum, ObjectCornersProjectInsideTheMap) {
  const scene::Aabb chair{dvec3(2.76, 0, 2.16), dvec3(3.24, 0.95, 2.64)};
  const std::array<dvec3, 5> sources = {dvec3(2.1, 3, 1.7), dvec3(3.0, 3.0, 2.4),
                                        dvec3(3.5, 1.5, 5.0), dvec3(0.1, 0.1, 0.1),
                                        dvec3(3.0, 0.5, 3.3)};
  for (const dvec3& s : sources) {
    const auto f = fitLightFrustum(s, chair, 12.0);
    ASSERT_TRUE(f.has_value());
    for (const dvec3& c : corners(chair)) {
      const auto q = clipOf(f->rasterViewProj, c);
      ASSERT_GT(q[3], 0);
      const float size = 256;
      const float u = (q[0] / q[3]) * (size / 2) + size / 2;
      const float v = -(q[1] / q[3]) * (size / 2) + size / 2;
      const float d = (q[2] / q[3]) * 0.5f + 0.5f;
      EXPECT_GE(u, 0);
      EXPECT_LT(u, size);
      EXPECT_GE(v, 0);
      EXPECT_LT(v, size);
      EXPECT_GT(d, 0);
      EXPECT_LT(d, 1);
    }
    EXPECT_GE(f->zNear, kMinLightNear);
    EXPECT_GE(f->zFar, 12.0);
  }
}

TEST(LightFrustum, FieldOfViewIsTight) {
  // A unit sphere's box seen from 10 m: the sphere touches the map's edge circle.
  const scene::Aabb box{dvec3(-1), dvec3(1)};
  const auto f = fitLightFrustum(dvec3(0, 0, 20), box, 50);
  ASSERT_TRUE(f.has_value());
  const double r = std::sqrt(3.0);
  EXPECT_NEAR(f->tanHalfFovY, r / std::sqrt(400 - 3), 1e-5);
  EXPECT_NEAR(f->zNear, (20 - r) * 0.999, 1e-9);
}

TEST(LightFrustum, SourceInsideTheSphereIsRejected) {
  const scene::Aabb box{dvec3(0), dvec3(1)};
  EXPECT_FALSE(fitLightFrustum(dvec3(0.5), box, 10).has_value());
  EXPECT_FALSE(
      fitLightFrustum(dvec3(1.1, 0.9, 0.5), box, 10).has_value());  // in sphere, out of box
  EXPECT_FALSE(fitLightFrustum(dvec3(5), scene::Aabb::emptyBox(), 10).has_value());
  EXPECT_TRUE(fitLightFrustum(dvec3(3, 3, 3), box, 10).has_value());
}

TEST(LightFrustum, NearPlaneClampedToOneMillimetre) {
  const scene::Aabb box{dvec3(-1), dvec3(1)};
  const double r = std::sqrt(3.0);
  const auto f = fitLightFrustum(dvec3(0, 0, r + 1e-4), box, 10);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->zNear, kMinLightNear);
}

TEST(LightFrustum, ReceiverTestIsConservative) {
  const scene::Aabb box{dvec3(-0.2, 0, -0.2), dvec3(0.2, 0.5, 0.2)};
  const auto f = fitLightFrustum(dvec3(0, 3, 0), box, 10);
  ASSERT_TRUE(f.has_value());
  // The floor under the object receives; a large triangle straddling the frustum too.
  EXPECT_TRUE(
      triangleMayReceive(f->viewProj, dvec3(-0.1, 0, -0.1), dvec3(0.1, 0, -0.1), dvec3(0, 0, 0.1)));
  EXPECT_TRUE(
      triangleMayReceive(f->viewProj, dvec3(-50, 0, -50), dvec3(50, 0, -50), dvec3(0, 0, 50)));
  // Far to the side, above the light (behind it), or between light and object: no.
  EXPECT_FALSE(triangleMayReceive(f->viewProj, dvec3(4, 0, 4), dvec3(5, 0, 4), dvec3(4, 0, 5)));
  EXPECT_FALSE(triangleMayReceive(f->viewProj, dvec3(-1, 4, -1), dvec3(1, 4, -1), dvec3(0, 4, 1)));
  EXPECT_FALSE(triangleMayReceive(f->viewProj, dvec3(-0.1, 2.5, -0.1), dvec3(0.1, 2.5, -0.1),
                                  dvec3(0, 2.5, 0.1)));
}

TEST(LightFrustum, OutcodesNameThePlanesAPointIsOutside) {
  const scene::Aabb box{dvec3(-0.2, 0, -0.2), dvec3(0.2, 0.5, 0.2)};
  const auto f = fitLightFrustum(dvec3(0, 3, 0), box, 10);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(clipOutcode(f->viewProj, dvec3(0, 0, 0)), 0);  // under the object
  // Between the light and the object: in front of the near plane (bit 4) only.
  EXPECT_EQ(clipOutcode(f->viewProj, dvec3(0, 2.9, 0)), 1 << 4);
  // Far to one side: outside one x or y plane and no other.
  const uint8_t side = clipOutcode(f->viewProj, dvec3(5, 0, 0));
  EXPECT_NE(side, 0);
  EXPECT_EQ(side & (side - 1), 0);
  EXPECT_EQ(side & 0x30, 0);
}

}  // namespace
}  // namespace penumbra::shadow
