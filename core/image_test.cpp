#include "core/image.h"

#include <gtest/gtest.h>

namespace penumbra::core {
namespace {

TEST(Image, Image8IsRowMajorWithInterleavedChannels) {
  Image8 img(4, 3, 3, "rgb");
  EXPECT_EQ(img.pixelCount(), 12u);
  ASSERT_EQ(img.pixels.size(), 36u);
  EXPECT_TRUE(img.hasExpectedSize());
  uint8_t* p = img.pixel(2, 1);
  p[0] = 10, p[1] = 20, p[2] = 30;
  // (y·width + x)·channels = (1·4 + 2)·3 = 18
  EXPECT_EQ(img.pixels[18], 10);
  EXPECT_EQ(img.pixels[19], 20);
  EXPECT_EQ(img.pixels[20], 30);
  EXPECT_EQ(img.name, "rgb");
  const Image8& c = img;
  EXPECT_EQ(c.pixel(3, 2), img.pixels.data() + 33);
}

TEST(Image, Image8MaskHasOneChannelAndAFill) {
  const Image8 mask(5, 2, 1, "mask", 7);
  ASSERT_EQ(mask.pixels.size(), 10u);
  for (uint8_t v : mask.pixels) EXPECT_EQ(v, 7);
  EXPECT_EQ(mask.pixel(4, 1), mask.pixels.data() + 9);
}

TEST(Image, HasExpectedSizeCatchesAShortBuffer) {
  Image8 img(4, 4, 3, "short");
  img.pixels.pop_back();
  EXPECT_FALSE(img.hasExpectedSize());
  ImageF f(2, 2);
  EXPECT_TRUE(f.hasExpectedSize());
  f.pixels.push_back(0.0f);
  EXPECT_FALSE(f.hasExpectedSize());
  EXPECT_TRUE(Image8().hasExpectedSize());  // empty is consistent
}

TEST(Image, ImageFIsRgbRowMajor) {
  ImageF img(3, 2, 0.5f);
  ASSERT_EQ(img.pixels.size(), 18u);
  for (float v : img.pixels) EXPECT_EQ(v, 0.5f);
  img.pixel(1, 1)[2] = 4.0f;
  EXPECT_EQ(img.pixels[(1 * 3 + 1) * 3 + 2], 4.0f);
}

}  // namespace
}  // namespace penumbra::core
