#include "envmap/reinhard_tonemap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "envmap/portable_log_exp.h"

namespace penumbra::envmap {
namespace {

TEST(PortableLogExp, AgreesWithLibmToAFewUlp) {
  for (double x = 1e-300; x < 1e300; x *= 1.37) {
    EXPECT_NEAR(portableLog(x), std::log(x), 4e-16 * std::max(1.0, std::fabs(std::log(x)))) << x;
  }
  for (double x = 0.5; x < 2.0; x += 0.001) EXPECT_NEAR(portableLog(x), std::log(x), 3e-16) << x;
  for (double x = -700; x < 700; x += 0.37) {
    EXPECT_NEAR(portableExp(x), std::exp(x), 4e-16 * std::exp(x)) << x;
  }
  EXPECT_EQ(portableExp(0.0), 1.0);
  EXPECT_EQ(portableLog(1.0), 0.0);
  EXPECT_EQ(portableLog(0.0), -INFINITY);
  EXPECT_TRUE(std::isnan(portableLog(-1.0)));
  EXPECT_EQ(portableExp(-800.0), 0.0);
  EXPECT_EQ(portableExp(800.0), INFINITY);
}

core::ImageF greyImage(std::initializer_list<float> values) {
  core::ImageF image(uint32_t(values.size()), 1);
  size_t i = 0;
  for (float v : values) {
    for (int c = 0; c < 3; ++c) image.pixels[i * 3 + c] = v;
    ++i;
  }
  return image;
}

// sRGB code of a linear value, from libm (the test's independent reference).
int srgbReference(double v) {
  v = std::min(1.0, v);
  const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
  return int(std::floor(e * 255 + 0.5));
}

// Reinhard 2002 eqs. 1, 2, 4 computed here with libm for grey pixels (luminance = value).
TEST(ReinhardToneMap, FollowsThePhotographicOperator) {
  const core::ImageF image = greyImage({0.01f, 0.1f, 1.0f, 10.0f, 100.0f});
  ReinhardToneMapper mapper({0.18, 1.0, 1e-4});
  const core::Image8 out = mapper.map(image);
  double logSum = 0;
  for (float v : {0.01f, 0.1f, 1.0f, 10.0f, 100.0f}) logSum += std::log(1e-4 + double(v));
  const double world = std::exp(logSum / 5);
  EXPECT_NEAR(mapper.worldLuminance(), world, 1e-12 * world);
  const double white = 0.18 / world * 100.0;
  EXPECT_NEAR(mapper.white(), white, 1e-12 * white);
  for (int i = 0; i < 5; ++i) {
    const double lw = image.pixels[i * 3];
    const double l = 0.18 / world * lw;
    const double ld = l * (1 + l / (white * white)) / (1 + l);
    EXPECT_NEAR(out.pixels[i * 3], srgbReference(ld), 1) << "pixel " << i;
  }
  EXPECT_EQ(out.pixels[4 * 3], 255);  // the brightest pixel is white (Lwhite = its L)
}

// Reinhard 2002b's automatic key: a mostly dark image (log-average near the bottom of its
// range) gets a low key, a mostly bright one a high key.
TEST(ReinhardToneMap, AutomaticKeyFollowsTheLogRange) {
  ReinhardToneMapper low({0.0, 1.0, 1e-4}), high({0.0, 1.0, 1e-4});
  low.map(greyImage({0.01f, 0.01f, 0.01f, 0.01f, 0.02f, 10.0f}));
  high.map(greyImage({0.01f, 8.0f, 9.0f, 10.0f, 10.0f, 10.0f}));
  EXPECT_LT(low.key(), 0.1);
  EXPECT_GT(high.key(), 0.3);
}

// Havran 2005 §5.1: the parameters are smoothed over time. A room (0.5) with a lamp (two
// pixels at 20); a bright object (a tenth of the image at 100) enters at frame 10:
// unsmoothed, the background's code drops in one frame;
// smoothed (s = 0.1), its largest step is under a third of that jump and it settles within
// a code of the unsmoothed value after 60 frames (measured: a 22-code jump; steps of 2).
TEST(ReinhardToneMap, SmoothingSpreadsABrightnessJumpOverTime) {
  core::ImageF before(100, 1, 0.5f);
  for (size_t i = 90 * 3; i < 92 * 3; ++i) before.pixels[i] = 20.0f;  // the lamp
  core::ImageF after = before;
  for (size_t i = 0; i < 30; ++i) after.pixels[i] = 100.0f;  // pixels 0–9
  auto background = [](const core::Image8& image) { return int(image.pixels[50 * 3]); };
  ReinhardToneMapper sharp({0.18, 1.0, 1e-4}), smooth({0.18, 0.1, 1e-4});
  int sharpPrevious = 0, smoothPrevious = 0, sharpJump = 0, smoothStep = 0;
  for (int frame = 0; frame < 70; ++frame) {
    const core::ImageF& image = frame < 10 ? before : after;
    const int a = background(sharp.map(image)), b = background(smooth.map(image));
    if (frame > 0) {
      sharpJump = std::max(sharpJump, std::abs(a - sharpPrevious));
      smoothStep = std::max(smoothStep, std::abs(b - smoothPrevious));
    }
    sharpPrevious = a, smoothPrevious = b;
  }
  std::printf("background code: unsmoothed jump %d, smoothed largest step %d\n", sharpJump,
              smoothStep);
  EXPECT_GT(sharpJump, 15);
  EXPECT_LT(smoothStep * 3, sharpJump) << "smoothed step " << smoothStep << ", jump " << sharpJump;
  EXPECT_NEAR(smoothPrevious, sharpPrevious, 1);
}

TEST(ReinhardToneMap, BadInputIsRefusedWithItsName) {
  core::ImageF image(4, 2, 1.0f);
  image.pixel(3, 1)[2] = -1.0f;
  ReinhardToneMapper mapper;
  try {
    mapper.map(image, "frame_0007.exr");
    FAIL() << "negative radiance accepted";
  } catch (const ToneMapError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_0007.exr: pixel (3, 1)"), std::string::npos)
        << e.what();
  }
  image.pixels.pop_back();
  EXPECT_THROW(mapper.map(image), ToneMapError);
  EXPECT_THROW(mapper.map(core::ImageF()), ToneMapError);
  EXPECT_THROW(ReinhardToneMapper({0.18, 0.0, 1e-4}), ToneMapError);
  EXPECT_THROW(ReinhardToneMapper({-1.0, 0.5, 1e-4}), ToneMapError);
}

}  // namespace
}  // namespace penumbra::envmap
