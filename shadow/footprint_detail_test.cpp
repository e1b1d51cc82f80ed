#include "shadow/footprint_detail.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "shadow/frame_loop.h"
#include "tests/camera_view.h"
#include "tests/showroom_bundle.h"

namespace penumbra::shadow {
namespace {

// A 640x480 camera at (0, 1, 0) looking along -z with a 60° vertical field of view.
raster::StaticView testView() {
  return testing::cameraView(glm::dvec3(0, 1, 0), glm::dvec3(0, 1, -1), glm::dvec3(0, 1, 0));
}

// 2 texels per pixel, the whole ceiling from 160 pixels: round numbers for the tests.
constexpr FootprintDetailOptions kTestOptions{160, 2, 4, 4};

// The sphere holds every vertex at every yaw: centred on the axis at mid-height.
TEST(FootprintDetail, YawSphereHoldsTheMeshAtEveryYaw) {
  core::Mesh m;
  m.positions = {{0.3f, 0.0f, 0.1f}, {-0.2f, 0.8f, 0.0f}, {0.0f, 0.4f, -0.4f}};
  const YawSphere s = yawSphere(m);
  EXPECT_NEAR(s.centreY, 0.4, 1e-7);
  EXPECT_NEAR(s.radius, std::sqrt(0.3 * 0.3 + 0.4 * 0.4 + 0.1 * 0.1), 1e-6);  // the first
}

// The footprint is the sphere's diameter in pixels: 2 r f / depth, f = (height / 2) /
// tan(fov / 2), the camera's focal length; +inf with the camera inside the sphere.
TEST(FootprintDetail, FootprintIsTheSpheresProjectedDiameter) {
  const raster::StaticView view = testView();
  const YawSphere sphere{0.5, 0.5};
  const double focal = testing::kFocalPx;
  for (const float z : {-2.0f, -4.0f, -8.0f}) {
    const ProductPose pose{0, 0.3f, z, 45.0f, 0.5f};
    const double depth = -double(z);
    EXPECT_NEAR(productFootprintPx(view, sphere, pose), 2.0 * 0.5 * focal / depth, 1e-4) << z;
  }
  EXPECT_TRUE(std::isinf(productFootprintPx(view, sphere, ProductPose{0, 0, -0.3f, 0, 0})));
  EXPECT_TRUE(std::isinf(productFootprintPx(view, sphere, ProductPose{0, 0, 3.0f, 0, 0})));
}

// A product walking away from the camera: the footprint shrinks 0.5 % a frame from 400 to
// 20 pixels. The maps step down the ladder once per rung and never back; the pass ceiling
// only falls, by at most 4 a frame; the map is never coarser than 2 texels per pixel.
TEST(FootprintDetail, ARecedingProductStepsDownWithoutGoingBack) {
  FootprintDetail detail(kTestOptions, 64, {256, 128, 64});
  FootprintDetail::Limits last = detail.next(400.0);
  EXPECT_EQ(last.passes, 64u);
  EXPECT_EQ(last.shadowMapSize, 256u);
  int mapChanges = 0;
  for (double d = 400.0; d > 20.0; d *= 0.995) {
    const FootprintDetail::Limits l = detail.next(d);
    EXPECT_LE(l.passes, last.passes) << d;
    EXPECT_LE(last.passes - l.passes, 4u) << d;
    EXPECT_LE(l.shadowMapSize, last.shadowMapSize) << d;
    if (l.shadowMapSize >= 2.0 * d || l.shadowMapSize == 256u) {
      // fine: at least 2 texels per pixel, or the largest map
    } else {
      ADD_FAILURE() << "map " << l.shadowMapSize << " for a footprint of " << d;
    }
    mapChanges += l.shadowMapSize != last.shadowMapSize;
    last = l;
  }
  EXPECT_EQ(mapChanges, 2);
  EXPECT_EQ(last.shadowMapSize, 64u);
  // The target ceil(64 · 20.1 / 160) = 9, kept to within the dead band of an eighth.
  EXPECT_GE(last.passes, 9u);
  EXPECT_LE(last.passes, 10u);
}

// A footprint wavering ±4 % around a rung's boundary (64 px: 128 texels at 2 per pixel) and
// around a pass target changes nothing once settled.
TEST(FootprintDetail, AWaveringFootprintChangesNothing) {
  FootprintDetail detail(kTestOptions, 64, {256, 128, 64});
  FootprintDetail::Limits settled{};
  for (int f = 0; f < 40; ++f) settled = detail.next(64.0);
  for (int f = 0; f < 400; ++f) {
    const FootprintDetail::Limits l = detail.next(f % 2 ? 66.5 : 61.5);
    EXPECT_EQ(l.shadowMapSize, settled.shadowMapSize) << f;
    EXPECT_EQ(l.passes, settled.passes) << f;
  }
}

// Coming closer, the map grows as soon as it would be coarser than 2 texels per pixel;
// off (fullDetailPx 0), unknown or infinite footprints get full detail.
TEST(FootprintDetail, ApproachingGrowsAtOnceAndOffIsFullDetail) {
  FootprintDetail detail(kTestOptions, 64, {256, 128, 64});
  for (int f = 0; f < 40; ++f) detail.next(20.0);
  EXPECT_EQ(detail.next(20.0).shadowMapSize, 64u);
  EXPECT_EQ(detail.next(33.0).shadowMapSize, 128u);
  EXPECT_EQ(detail.next(65.0).shadowMapSize, 256u);
  EXPECT_EQ(detail.next(std::nan("")).shadowMapSize, 256u);
  FootprintDetailOptions off;
  off.fullDetailPx = 0;
  FootprintDetail none(off, 48, {512, 256, 128});
  const FootprintDetail::Limits l = none.next(5.0);
  EXPECT_EQ(l.passes, 48u);
  EXPECT_EQ(l.shadowMapSize, 512u);
  EXPECT_THROW(FootprintDetail({}, 0, {256}), std::invalid_argument);
  EXPECT_THROW(FootprintDetail({}, 8, {}), std::invalid_argument);
}

// What the caps change on screen (no popping): the teapot in the showroom's far corner (a
// footprint of about 37 pixels, the smallest of the shipped showroom with a visible shadow),
// drawn at full detail and at the capped passes and map: with the defaults (fewer passes) and
// with 2 texels per pixel (a 128² map as well). Either cap changes the shadow by less than
// one level on average (the display's own step) and less than a 2 cm step of the product does
// at full detail (the kiosk's finest move is 10 cm).
TEST(FootprintDetail, TheCapsChangeAFarShadowLessThanAStepOfTheProduct) {
  const SceneBundle& bundle = testing::showroomBundle();
  const ProductPose far{2, 4.5f, 4.5f, 0.0f, 0.0f};
  const double px = productFootprintPx(bundle.view, yawSphere(bundle.products[2].mesh), far);
  auto capsFor = [&](const FootprintDetailOptions& o) {
    FootprintDetail detail(o, 64, {256, 128, 64});
    FootprintDetail::Limits l{};
    for (int f = 0; f < 40; ++f) l = detail.next(px);
    return l;
  };
  const FootprintDetail::Limits defaults = capsFor({});
  FootprintDetailOptions coarse;
  coarse.texelsPerPixel = 2;
  const FootprintDetail::Limits smaller = capsFor(coarse);
  EXPECT_LT(defaults.passes, 64u) << px;
  EXPECT_EQ(defaults.shadowMapSize, 256u) << px;
  EXPECT_EQ(smaller.shadowMapSize, 128u) << px;
  auto frame = [&](const ProductPose& pose, size_t passes, uint32_t map) {
    FrameLoop loop(bundle, map, {});
    loop.still(pose, passes);
    return loop.rgba;
  };
  ProductPose moved = far;
  moved.x += 0.02f;
  const std::vector<uint8_t> unshadowed = frame(far, 0, 256), full = frame(far, 64, 256);
  const std::vector<uint8_t> step = frame(moved, 64, 256), stepUnshadowed = frame(moved, 0, 256);
  const std::vector<uint8_t> capped = frame(far, defaults.passes, defaults.shadowMapSize);
  const std::vector<uint8_t> small = frame(far, smaller.passes, smaller.shadowMapSize);
  double cappedDiff = 0, smallDiff = 0, stepDiff = 0;
  size_t shadow = 0;
  for (size_t i = 0; i < full.size(); i += 4) {
    // The shadow of either pose: where it differs from its own unshadowed frame.
    bool inShadow = false;
    for (size_t c = 0; c < 3; ++c) {
      inShadow |= full[i + c] != unshadowed[i + c] || step[i + c] != stepUnshadowed[i + c];
    }
    if (!inShadow) continue;
    ++shadow;
    for (size_t c = 0; c < 3; ++c) {
      cappedDiff += std::abs(int(full[i + c]) - int(capped[i + c]));
      smallDiff += std::abs(int(full[i + c]) - int(small[i + c]));
      stepDiff += std::abs(int(full[i + c]) - int(step[i + c]));
    }
  }
  ASSERT_GT(shadow, 100u);
  const double n = 3.0 * double(shadow);
  std::printf(
      "footprint %.1f px, shadow %zu px: %u passes change it %.3f levels, %u passes on "
      "%u² %.3f, a 2 cm step %.3f\n",
      px, shadow, defaults.passes, cappedDiff / n, smaller.passes, smaller.shadowMapSize,
      smallDiff / n, stepDiff / n);
  EXPECT_LT(cappedDiff / n, 1.0);
  EXPECT_LT(smallDiff / n, 1.0);
  EXPECT_LT(cappedDiff, stepDiff);
  EXPECT_LT(smallDiff, stepDiff);
}

}  // namespace
}  // namespace penumbra::shadow
