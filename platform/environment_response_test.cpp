// The environment camera's linearisation (platform/environment_response.h): the table inverts
// the sRGB encoding and a gamma within 8-bit quantisation, divides by the exposure, reads
// OpenCV's BGR order, and counts saturated pixels.
#include "platform/environment_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace penumbra::platform {
namespace {

double srgbDecode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

TEST(EnvironmentResponse, SrgbTableInvertsTheEncodingWithinQuantisation) {
  const auto table = inverseResponse(0, 1);
  EXPECT_EQ(table[0], 0.0f);
  EXPECT_EQ(table[255], 1.0f);
  for (int v = 0; v < 256; ++v) {
    // The table is IEC 61966-2-1's curve (portable exp/log against libm's pow: float-equal).
    EXPECT_NEAR(table[size_t(v)], srgbDecode(v / 255.0), 1e-7 + 1e-6 * srgbDecode(v / 255.0)) << v;
    if (v > 0) {
      EXPECT_GT(table[size_t(v)], table[size_t(v - 1)]) << v;  // monotonic
    }
  }
  // Encoding a linear value to 8 bits and looking it up gives it back within half a step of
  // the curve at that value.
  for (int i = 0; i <= 1000; ++i) {
    const double linear = i / 1000.0;
    const uint8_t v = encodeSrgb8(linear);
    const double lo = srgbDecode(std::max(0.0, (v - 0.5) / 255.0));
    const double hi = srgbDecode(std::min(1.0, (v + 0.5) / 255.0));
    EXPECT_GE(linear, lo - 1e-12) << linear;
    EXPECT_LE(linear, hi + 1e-12) << linear;
    EXPECT_GE(table[v], lo - 1e-7) << linear;
    EXPECT_LE(table[v], hi + 1e-7) << linear;
  }
  EXPECT_EQ(encodeSrgb8(0.5), 188);  // the textbook value: sRGB 188 is 50 % linear
}

TEST(EnvironmentResponse, GammaAndExposureScale) {
  const auto gamma = inverseResponse(2.2, 1);
  EXPECT_NEAR(gamma[128], std::pow(128 / 255.0, 2.2), 1e-7);
  const auto scaled = inverseResponse(0, 4);
  for (size_t v = 0; v < 256; ++v) EXPECT_FLOAT_EQ(scaled[v], inverseResponse(0, 1)[v] / 4) << v;
  EXPECT_THROW(inverseResponse(-1, 1), std::invalid_argument);
  EXPECT_THROW(inverseResponse(0, 0), std::invalid_argument);
  EXPECT_THROW(inverseResponse(NAN, 1), std::invalid_argument);
}

TEST(EnvironmentResponse, LinearisesBgrAndCountsSaturatedPixels) {
  const auto table = inverseResponse(0, 1);
  const ChannelTables tables{table, table, table};
  // 3 × 2 pixels, rows 12 bytes apart (3 padding bytes): BGR order.
  const std::vector<uint8_t> frame{10,  20,  30,  250, 0,  0,   1, 2, 3, 99, 99, 99,
                                   255, 255, 255, 40,  50, 249, 0, 0, 0, 99, 99, 99};
  core::ImageF image;
  EXPECT_EQ(linearise(frame.data(), 12, 3, 2, tables, image), 2u);
  ASSERT_EQ(image.width, 3u);
  ASSERT_EQ(image.height, 2u);
  EXPECT_EQ(image.pixel(0, 0)[0], table[30]);  // red from the third byte
  EXPECT_EQ(image.pixel(0, 0)[1], table[20]);
  EXPECT_EQ(image.pixel(0, 0)[2], table[10]);
  EXPECT_EQ(image.pixel(1, 1)[0], table[249]);
  EXPECT_EQ(image.pixel(2, 1)[2], 0.0f);
}

}  // namespace
}  // namespace penumbra::platform
