#include "scene/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace penumbra::scene {
namespace {

TEST(Texture, SrgbDecodingMatchesTheStandardWithoutLibmInTheTable) {
  EXPECT_EQ(srgbToLinear(0), 0.0);
  EXPECT_EQ(srgbToLinear(255), 1.0);
  EXPECT_EQ(srgbToLinear(10), 10 / 255.0 / 12.92);  // the linear segment
  double previous = -1;
  for (int c = 0; c < 256; ++c) {
    const double v = c / 255.0;
    const double want = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    EXPECT_NEAR(srgbToLinear(uint8_t(c)), want, 4e-16) << c;  // within 2 ulp of libm's
    EXPECT_GT(srgbToLinear(uint8_t(c)), previous);
    previous = srgbToLinear(uint8_t(c));
  }
}

Texture twoByOne() {
  // Red | blue (linear values, as decoded).
  return Texture{2, 1, {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1)}};
}

TEST(Texture, BilinearSamplingAndWrapModes) {
  const Texture t = twoByOne();
  const auto red = glm::dvec3(1, 0, 0), blue = glm::dvec3(0, 0, 1), mix = glm::dvec3(0.5, 0, 0.5);
  // Texel centres read the texel.
  EXPECT_EQ(sampleBilinear(t, 0.25, 0.5, TextureWrap::kRepeat, TextureWrap::kRepeat), red);
  EXPECT_EQ(sampleBilinear(t, 0.75, 0.5, TextureWrap::kRepeat, TextureWrap::kRepeat), blue);
  EXPECT_EQ(sampleBilinear(t, 0.5, 0.5, TextureWrap::kRepeat, TextureWrap::kRepeat), mix);
  // The edge: repeat blends with the other side, clamp does not, mirror reflects.
  EXPECT_EQ(sampleBilinear(t, 0.0, 0.5, TextureWrap::kRepeat, TextureWrap::kRepeat), mix);
  EXPECT_EQ(sampleBilinear(t, 0.0, 0.5, TextureWrap::kClampToEdge, TextureWrap::kRepeat), red);
  EXPECT_EQ(sampleBilinear(t, 0.0, 0.5, TextureWrap::kMirroredRepeat, TextureWrap::kRepeat), red);
  EXPECT_EQ(sampleBilinear(t, 1.25, 0.5, TextureWrap::kRepeat, TextureWrap::kRepeat), red);
  EXPECT_EQ(sampleBilinear(t, 1.25, 0.5, TextureWrap::kMirroredRepeat, TextureWrap::kRepeat), blue);
  EXPECT_EQ(sampleBilinear(t, 7.0, -3.0, TextureWrap::kClampToEdge, TextureWrap::kClampToEdge),
            blue);
  // Far-away coordinates stay finite and in range.
  const glm::dvec3 far =
      sampleBilinear(t, 1e12 + 0.25, -1e12, TextureWrap::kRepeat, TextureWrap::kMirroredRepeat);
  EXPECT_TRUE(far.x >= 0 && far.x <= 1 && far.z >= 0 && far.z <= 1);
}

TEST(Texture, PpmDecodesAndCorruptImagesAreNamed) {
  const std::string p6 = std::string("P6\n# c\n2 1\n255\n") + char(255) + char(0) + char(0) +
                         char(0) + char(0) + char(188);
  const std::optional<Texture> t = decodeTexture(p6, "t.ppm");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->width, 2u);
  EXPECT_EQ(t->texels[0], glm::dvec3(1, 0, 0));
  EXPECT_EQ(t->texels[1], glm::dvec3(0, 0, srgbToLinear(188)));
  const std::optional<Texture> ascii = decodeTexture("P3 1 1 15 15 0 15", "a.ppm");
  ASSERT_TRUE(ascii);
  EXPECT_EQ(ascii->texels[0], glm::dvec3(1, 0, 1));
  const auto error = [](const std::string& bytes) {
    try {
      decodeTexture(bytes, "bad.img");
    } catch (const TextureError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("GIF89a").find("bad.img: not a PNG, JPEG or PPM"), std::string::npos);
  EXPECT_NE(error("P6 2 2 255\nab").find("truncated"), std::string::npos);
  EXPECT_NE(error("P6 0 2 255\n").find("0 x 2 pixels"), std::string::npos);
  EXPECT_NE(error("P6 9000 2 255\n").find("9000 x 2 pixels"), std::string::npos);
  EXPECT_NE(error("P3 1 1 255 256 0 0").find("above maxval"), std::string::npos);
  // A PNG header announcing 65535 x 65535 pixels is refused before decoding.
  std::string png = "\x89PNG\r\n\x1a\n";
  png += std::string("\0\0\0\x0dIHDR\0\0\xff\xff\0\0\xff\xff\x08\x02\0\0\0", 21);
  EXPECT_NE(error(png).find("65535 x 65535 pixels"), std::string::npos);
  EXPECT_NE(error("\x89PNG\r\n\x1a\nxx").find("truncated PNG header"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::scene
