#include "scene/camera_intrinsics.h"

#include <gtest/gtest.h>

#include "scene/calibration_test_util.h"

namespace penumbra::scene {
namespace {

// The renderer's camera from toCamera() must put every world point on the pixel the
// calibrated camera does (no distortion, principal point at the centre): window x =
// u + 0.5 (pipeline-spec §2 viewport), row 0 at the top.
TEST(CameraIntrinsics, RendererCameraProjectsLikeTheCalibratedOne) {
  Intrinsics k;
  k.width = 640;
  k.height = 480;
  k.fx = 610;
  k.fy = 590;  // non-square pixels too
  k.cx = 319.5;
  k.cy = 239.5;
  const Pose pose = testutil::lookFrom({3.0, 1.6, 4.0}, {0.4, 0.5, 0.3});
  double offset = -1;
  const Camera cam = toCamera(k, pose, 0.05, 50, &offset);
  EXPECT_NEAR(offset, 0.0, 1e-12);
  const glm::dmat4 vp = cam.viewProj();
  for (const glm::dvec3 w : {glm::dvec3(0, 0, 0), glm::dvec3(1.5, 0, 0), glm::dvec3(0, 2, 0.5),
                             glm::dvec3(1, 0.7, 1.2), glm::dvec3(-0.5, 1.2, 2)}) {
    const glm::dvec4 clip = vp * glm::dvec4(w, 1.0);
    ASSERT_GT(clip.w, 0);
    const double xw = clip.x / clip.w * 320 + 320, yw = -clip.y / clip.w * 240 + 240;
    const glm::dvec2 uv = projectPoint(k, pose, w);
    EXPECT_NEAR(xw - 0.5, uv.x, 1e-9);
    EXPECT_NEAR(yw - 0.5, uv.y, 1e-9);
  }
  // And the ray through a pixel centre passes through the point seen there.
  const glm::dvec3 p(1, 0.7, 1.2);
  const glm::dvec2 uv = projectPoint(k, pose, p);
  const glm::dvec3 dir = cam.rayDirection(uv.x + 0.5, uv.y + 0.5, 640, 480);
  EXPECT_GT(glm::dot(dir, glm::normalize(p - cam.eye)), 1 - 1e-12);
  k.cx += 3;
  k.cy -= 4;
  toCamera(k, pose, 0.05, 50, &offset);
  EXPECT_NEAR(offset, 5.0, 1e-12);
  k.fx = 0;
  EXPECT_THROW(toCamera(k, pose, 0.05, 50), CalibrationError);
}

TEST(CameraIntrinsics, DistortionMatchesTheBrownConradyModel) {
  Intrinsics k;
  k.fx = k.fy = 500;
  k.cx = 320;
  k.cy = 240;
  k.k1 = -0.2;
  k.p1 = 0.01;
  // x = 0.2, y = -0.1: r^2 = 0.05, radial = 1 - 0.01 = 0.99,
  // xd = 0.198 + 2 * 0.01 * 0.2 * -0.1 = 0.1976, yd = -0.099 + 0.01 * (0.05 + 0.02) = -0.0983.
  const glm::dvec2 uv = k.project({0.4, -0.2, 2.0});
  EXPECT_NEAR(uv.x, 320 + 500 * 0.1976, 1e-9);
  EXPECT_NEAR(uv.y, 240 + 500 * -0.0983, 1e-9);
}

}  // namespace
}  // namespace penumbra::scene
