// Issue 15 item 4: firm contact shadows at every pass count. The bunny and the teapot of the
// bundled showroom, at the open-floor and desk-corner poses of bench/accuracy_poses.sh,
// against the ray-traced reference's contact band (reference/shadow_region.h: the shadow
// within 8 pixels of the product, where it meets the floor). The complaint was a band that
// faded as passes rose and, at the desk, a floor 40-50 levels too light at the desk's foot.
//
// Measured at this commit (mean abs / mean signed, levels; 20, 50, 82 passes):
//   bunny, open floor    5.18 / -1.57   2.19 / +1.29   2.07 / +1.26
//   bunny, desk corner   3.82 / +0.34   2.34 / +2.04   2.31 / +2.04
//   teapot, open floor   5.54 / -2.21   1.59 / +0.39   1.27 / +0.55
//   teapot, desk corner  3.72 / -0.97   1.48 / +0.96   1.42 / +0.91
// At 20 passes a cluster's whole share follows its representative's shadow map, so the band
// is too dark; from 50 on it is slightly light, and that is the 300-triangle shadow proxy:
// with 2000 the bunny's band measures +0.26 at 50 passes (docs/accuracy.md).
//
// The reference samples the pixel centres (ReferenceOptions::pixelCentres), as the
// rasterizer does, so the band measures the shadow and not the anti-aliasing of a
// point-sampled image; it is rendered only in a window around the product (~1 s a pose).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "reference/accuracy.h"
#include "tests/showroom_bundle.h"
#include "tests/test_workload.h"

namespace penumbra::reference {
namespace {

struct ContactCase {
  const char* name;
  shadow::ProductPose pose;
  // Measured under the sanitizers' small workload too (tests/test_workload.h): the bunny's
  // desk corner, the same code as the other three (all four took 110 s of the asan stage on
  // 2026-12-02, the two desk corners 41 s).
  bool smallWorkload;
};

// bench/accuracy_poses.sh's poses (product index, x, z, yaw, lift).
const ContactCase kCases[] = {
    {"bunny, open floor", {1, 3.0f, 2.4f, 0.0f, 0.0f}, false},
    {"bunny, desk corner", {1, 5.6f, 3.05f, 0.0f, 0.0f}, true},
    {"teapot, open floor", {2, 3.0f, 2.4f, 0.0f, 0.0f}, false},
    {"teapot, desk corner", {2, 5.6f, 3.05f, 0.0f, 0.0f}, false},
};

// The product's pixels, from its placed vertices through the camera, grown by `margin`.
ReferenceOptions::Window windowAround(const shadow::SceneBundle& b, const shadow::ProductPose& pose,
                                      int margin) {
  core::Mesh placed;
  shadow::placeMesh(b.products[pose.product].mesh, pose, placed);
  const auto& m = b.view.cameraViewProj.m;
  double x0 = b.view.width, y0 = b.view.height, x1 = 0, y1 = 0;
  for (const core::Vec3& p : placed.positions) {
    double clip[4];
    for (size_t r = 0; r < 4; ++r) {
      clip[r] = double(m[4 * r]) * p.x + double(m[4 * r + 1]) * p.y + double(m[4 * r + 2]) * p.z +
                double(m[4 * r + 3]);
    }
    const double px = (clip[0] / clip[3] + 1) * 0.5 * b.view.width;
    const double py = (1 - clip[1] / clip[3]) * 0.5 * b.view.height;
    x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
  }
  const auto clamp = [](double v, uint32_t hi) { return uint32_t(std::clamp(v, 0.0, double(hi))); };
  return {
      clamp(std::floor(x0) - margin, b.view.width), clamp(std::floor(y0) - margin, b.view.height),
      clamp(std::ceil(x1) + margin, b.view.width), clamp(std::ceil(y1) + margin, b.view.height)};
}

TEST(ContactShadow, FirmAtEveryPassCountAtTheBunnysAndTeapotsPoses) {
  if (!accuracyHasRayTracer()) GTEST_SKIP() << "built without the ray tracer";
  const shadow::SceneBundle& bundle = testing::showroomBundle();
  for (const ContactCase& c : kCases) {
    if (testing::smallTestWorkload() && !c.smallWorkload) continue;
    AccuracyOptions o;
    o.passes = {20, 50, 82};
    o.frames = 1;
    o.pose = c.pose;
    o.rays.samplesPerPixel = 16;
    o.rays.lightSamples = 32;
    o.rays.pixelCentres = true;
    o.rays.threads = 2;
    o.rays.window = windowAround(bundle, c.pose, 24);
    const AccuracyReport r = measureAccuracy(bundle, o);
    std::printf("%-20s window %ux%u:", c.name, o.rays.window->x1 - o.rays.window->x0,
                o.rays.window->y1 - o.rays.window->y0);
    for (const AccuracyRow& row : r.rows) {
      std::printf("  %d passes: band %llu px, mean abs %.2f, signed %+.2f;", row.passesAsked,
                  static_cast<unsigned long long>(row.contact.bandPixels), row.contact.meanAbs,
                  row.contact.meanSigned);
      ASSERT_GT(row.contact.bandPixels, 100u) << c.name;
      // Firm: at no pass count more than 2.5 levels too light on average (a faded band is
      // tens of levels light; before contact refinement the desk corners were +5.6 and +3.0
      // in the anti-aliased measure)...
      EXPECT_LE(row.contact.meanSigned, 2.5) << c.name << ", " << row.passesAsked << " passes";
      // ...and close from the kiosk's working pass counts on.
      if (row.passesAsked >= 50) {
        EXPECT_LE(row.contact.meanAbs, 3.0) << c.name << ", " << row.passesAsked << " passes";
      }
    }
    std::printf("\n");
    // Not fading as passes rise: all clusters (82) no lighter than 50 passes by more than half
    // a level (the reference's noise over a band of 100-600 pixels is ~0.1).
    EXPECT_LE(r.rows[2].contact.meanSigned - r.rows[1].contact.meanSigned, 0.5) << c.name;
  }
}

}  // namespace
}  // namespace penumbra::reference
