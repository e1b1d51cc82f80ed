// Live lighting end to end on the simulated board's side: a lat-long environment turning 5° a
// frame, photographed through a 256-pixel equidistant fisheye (envmap/fisheye_resampler.h),
// written as an EXR sequence, played by the virtual fisheye camera on the virtual clock
// (firmware-sim/virtual_fisheye_camera.h), resampled into the hemisphere map and turned into
// filtered lights (lighting/). Checks what each stage hands the next.
#ifdef PENUMBRA_HAVE_FOOTAGE
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/colour.h"
#include "envmap/envmap_sampling.h"
#include "envmap/fisheye_resampler.h"
#include "envmap/lat_long.h"
#include "envmap/light_filter.h"
#include "firmware-sim/virtual_fisheye_camera.h"
#include "tests/scratch_dir.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using namespace envmap;

TEST(LiveLightingCamera, FisheyeExrSequenceBecomesFilteredLights) {
  const fs::path dir = test::scratchPath("live-lighting-camera");
  fs::create_directories(dir);
  core::ImageF latLong(256, 128);
  for (uint32_t y = 0; y < 128; ++y)
    for (uint32_t x = 0; x < 256; ++x)
      for (int c = 0; c < 3; ++c)
        latLong.pixel(x, y)[c] = (x >= 40 && x < 52 && y >= 30 && y < 40) ? 100.0f : 0.4f;
  const FisheyeLens lens = FisheyeLens::equidistant180(256);
  // Where the light comes from: the luminance-weighted mean direction of a map.
  auto centroid = [](const HemisphereMap& m) {
    glm::dvec3 sum(0.0);
    for (uint32_t row = 0; row < m.rows(); ++row)
      for (uint32_t col = 0; col < m.cols(); ++col) {
        const float* p = m.radiance.pixel(col, row);
        sum += core::luminance(glm::dvec3(p[0], p[1], p[2])) * m.pixelCentre(col, row);
      }
    return glm::normalize(sum);
  };
  std::vector<double> expectedPower;
  std::vector<glm::dvec3> expectedCentroid;
  for (int k = 0; k < 6; ++k) {
    const core::ImageF image = renderFisheye(latLong, lens, 5.0 * k);
    cv::Mat bgr(int(image.height), int(image.width), CV_32FC3);
    for (uint32_t y = 0; y < image.height; ++y)
      for (uint32_t x = 0; x < image.width; ++x)
        for (int c = 0; c < 3; ++c) bgr.at<cv::Vec3f>(int(y), int(x))[2 - c] = image.pixel(x, y)[c];
    ASSERT_TRUE(cv::imwrite((dir / ("env_" + std::to_string(k) + ".exr")).string(), bgr));
    const HemisphereMap direct = hemisphereFromLatLong(latLong, 5.0 * k);
    expectedPower.push_back(EnvmapDistribution(direct).totalLuminancePower());
    expectedCentroid.push_back(centroid(direct));
  }
  firmware_sim::VirtualFisheyeCamera camera(firmware_sim::loadExrSequence(dir).frames);
  fs::remove_all(dir);
  const FisheyeResampler resampler(lens);
  const SamplePattern pattern(50);
  TemporalLightFilter filter;
  HemisphereMap map;
  EnvmapDistribution distribution(hemisphereFromLatLong(latLong));
  core::ImageF frame;
  uint64_t k = 0;
  for (int64_t t = 0; t < 6 * firmware_sim::VirtualFisheyeCamera::kDefaultPeriodNs;
       t += firmware_sim::VirtualFisheyeCamera::kDefaultPeriodNs / 2) {
    if (!camera.grab(t, frame, k)) continue;
    resampler.resample(frame, map, "env_" + std::to_string(k) + ".exr");
    distribution.update(map);
    // The camera's frame is the environment turned by 5k°: its power and where its light comes
    // from are the direct map's (within 0.5°: the lamp moves 5° a frame).
    EXPECT_NEAR(distribution.totalLuminancePower(), expectedPower[k], 0.03 * expectedPower[k]) << k;
    EXPECT_LT(std::acos(std::min(1.0, glm::dot(centroid(map), expectedCentroid[k]))) * 180 /
                  3.14159265358979323846,
              0.5)
        << k;
    const LightSet raw = distribution.sample(pattern, 50);
    const LightSet lights = filter.push(raw);
    ASSERT_EQ(lights.size(), 50u);
    for (uint32_t i = 0; i < 50; ++i) EXPECT_EQ(lights[i].id, i + 1);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(totalPower(raw)[c], distribution.totalPower()[c],
                  1e-12 * distribution.totalPower()[c]);
  }
  EXPECT_EQ(k, 5u);
  EXPECT_EQ(filter.framesPushed(), 6u);
}

}  // namespace
}  // namespace penumbra
#endif
