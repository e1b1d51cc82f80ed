#include "envmap/fisheye_resampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "envmap/envmap_sampling.h"
#include "envmap/lat_long.h"

namespace penumbra::envmap {
namespace {

// An image whose red and green channels are the pixel centre's coordinates: bilinear
// interpolation reproduces a linear function exactly, so the resampled map holds where each
// map pixel's direction landed in the image.
core::ImageF coordinateImage(uint32_t size) {
  core::ImageF image(size, size);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      image.pixel(x, y)[0] = float(x) + 0.5f;
      image.pixel(x, y)[1] = float(y) + 0.5f;
    }
  return image;
}

// cv::fisheye with k = 0 is the equidistant lens: image radius f·θ from the centre, at the
// azimuth of the direction (the map's frame is the camera's).
TEST(FisheyeResampler, ProjectsWithTheEquidistantModel) {
  const FisheyeLens lens = FisheyeLens::equidistant180(512);
  const FisheyeResampler resampler(lens, kEnvmapCols, kEnvmapRows, 1);
  HemisphereMap map;
  resampler.resample(coordinateImage(512), map);
  for (uint32_t row = 0; row < kEnvmapRows; row += 7)
    for (uint32_t col = 0; col < kEnvmapCols; col += 13) {
      const glm::dvec3 d = map.pixelCentre(col, row);
      const double theta = std::acos(d.z), phi = 2 * std::numbers::pi * (col + 0.5) / kEnvmapCols;
      const double x = lens.cx + lens.fx * theta * std::cos(phi);
      const double y = lens.cy + lens.fy * theta * std::sin(phi);
      EXPECT_NEAR(map.radiance.pixel(col, row)[0], x, 0.01) << col << ", " << row;
      EXPECT_NEAR(map.radiance.pixel(col, row)[1], y, 0.01) << col << ", " << row;
    }
}

// A lat-long environment (a sky and a bright lamp) photographed through the fisheye and
// resampled agrees with resampling the lat-long map directly: total power within 2%, the
// lamp's lights within 1.5° on average.
TEST(FisheyeResampler, FisheyePhotographResamplesLikeTheEnvironment) {
  core::ImageF latLong(512, 256);
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 512; ++x) {
      float* p = latLong.pixel(x, y);
      const bool lamp = x >= 100 && x < 116 && y >= 60 && y < 72;
      for (int c = 0; c < 3; ++c) p[c] = lamp ? 200.0f : 0.5f + 0.3f * float(c) * float(y) / 256;
    }
  const HemisphereMap direct = hemisphereFromLatLong(latLong, 30.0);
  const FisheyeLens lens = FisheyeLens::equidistant180(640);
  HemisphereMap viaCamera;
  FisheyeResampler(lens).resample(renderFisheye(latLong, lens, 30.0), viaCamera);
  const EnvmapDistribution a(direct), b(viaCamera);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(b.totalPower()[c], a.totalPower()[c], 0.02 * a.totalPower()[c]) << c;
  const SamplePattern pattern(100);
  const LightSet la = a.sample(pattern, 100), lb = b.sample(pattern, 100);
  double meanAngle = 0;
  for (size_t i = 0; i < la.size(); ++i)
    meanAngle += std::acos(std::min(1.0, glm::dot(la[i].direction, lb[i].direction)));
  EXPECT_LT(meanAngle / 100 * 180 / std::numbers::pi, 1.5);
}

TEST(FisheyeResampler, BadLensesAndFramesAreRefused) {
  FisheyeLens narrow = FisheyeLens::equidistant180(256);
  narrow.fx = narrow.fy = 2 * narrow.fx;  // a 90° lens: the horizon is outside the image
  EXPECT_THROW(FisheyeResampler{narrow}, FisheyeError);
  EXPECT_THROW(FisheyeResampler{FisheyeLens{}}, FisheyeError);
  const FisheyeResampler resampler(FisheyeLens::equidistant180(64), 36, 9);
  HemisphereMap map;
  try {
    resampler.resample(core::ImageF(64, 32), map, "env_0003.exr");
    FAIL() << "a frame of the wrong size accepted";
  } catch (const FisheyeError& e) {
    EXPECT_NE(std::string(e.what()).find("env_0003.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("64 × 32"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::envmap
