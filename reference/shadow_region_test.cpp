#include "reference/shadow_region.h"

#include <gtest/gtest.h>

namespace penumbra::reference {
namespace {

// A 6x1 strip: background grey 100, the product at pixel 0 (grey 200 in the shadow-free
// frame). Pixel indices below are x.
struct Strip {
  static constexpr uint32_t kWidth = 6, kHeight = 1;
  std::vector<uint8_t> background = std::vector<uint8_t>(kWidth * 4, 100);
  std::vector<uint8_t> unshadowed = background;
  core::Image8 reference{kWidth, kHeight, 3, "reference", 100};

  Strip() {
    for (size_t k = 0; k < 3; ++k) unshadowed[k] = 200;
    for (size_t k = 0; k < 3; ++k) reference.pixels[k] = 150;  // the reference shades it otherwise
  }
  void setReference(size_t x, size_t channel, uint8_t v) { reference.pixels[3 * x + channel] = v; }
  static void set(std::vector<uint8_t>& rgba, size_t x, size_t channel, uint8_t v) {
    rgba[4 * x + channel] = v;
  }
};

TEST(ShadowRegion, ProductPixelsAreWhereTheShadowFreeFrameLeavesTheBackground) {
  Strip s;
  Strip::set(s.unshadowed, 3, 2, 101);  // one channel, one level: still the product
  EXPECT_EQ(productPixels(s.unshadowed, s.background, s.kWidth, s.kHeight),
            (std::vector<uint8_t>{1, 0, 0, 1, 0, 0}));
}

TEST(ShadowRegion, OneLevelInOneChannelCountsAndTheProductNeverDoes) {
  Strip s;
  s.setReference(1, 1, 99);  // one level darker in green
  s.setReference(2, 0, 60);
  s.setReference(4, 2, 101);  // lighter counts too: the shadow "changes a byte"
  const core::Image8 m = shadowRegion(s.reference, s.unshadowed, s.background, "region");
  EXPECT_EQ(m.width, s.kWidth);
  EXPECT_EQ(m.height, s.kHeight);
  EXPECT_EQ(m.name, "region");
  EXPECT_EQ(m.channels, 1u);
  // Pixel 0 differs (150 against 200) but is the product's own.
  EXPECT_EQ(m.pixels, (std::vector<uint8_t>{0, 1, 1, 0, 1, 0}));
}

TEST(ShadowRegion, AGivenMaskLosesThePixelsThisFrameDrawsTheProductOn) {
  Strip s;
  Strip::set(s.unshadowed, 3, 0, 180);  // the rasterized product also covers pixel 3
  core::Image8 mask(s.kWidth, s.kHeight, 1, "ray-traced mask");
  mask.pixels = {0, 1, 1, 1, 0, 1};
  excludeProductPixels(mask, s.unshadowed, s.background);
  EXPECT_EQ(mask.pixels, (std::vector<uint8_t>{0, 1, 1, 0, 0, 1}));
  core::Image8 small(5, 1, 1, "small");
  EXPECT_THROW(excludeProductPixels(small, s.unshadowed, s.background), MetricsError);
}

TEST(ShadowRegion, RejectsImagesOfAnotherSize) {
  Strip s;
  std::vector<uint8_t> small(4 * 5, 100);
  EXPECT_THROW(shadowRegion(s.reference, small, s.background, "r"), MetricsError);
  EXPECT_THROW(shadowRegion(s.reference, s.unshadowed, small, "r"), MetricsError);
  EXPECT_THROW(productPixels(s.unshadowed, s.background, 5, 1), MetricsError);
}

// Region {1, 2, 4}; radius 1 puts pixel 1 (next to the product) in the band, not 2 or 4.
// The frame is 6 levels lighter than the reference at 1 in every channel, so the band's mean
// abs and signed errors are 6 and +6; outside the region, pixel 3 is darkened by 3 levels
// (spurious) and pixel 5 by 2 (not).
TEST(ShadowRegion, ContactBandAndSpuriousShadowByHand) {
  Strip s;
  for (size_t k = 0; k < 3; ++k) {
    s.setReference(1, k, 40);
    s.setReference(2, k, 50);
    s.setReference(4, k, 70);
  }
  const core::Image8 region = shadowRegion(s.reference, s.unshadowed, s.background, "region");
  std::vector<uint8_t> frame = s.unshadowed;
  for (size_t k = 0; k < 3; ++k) {
    Strip::set(frame, 1, k, 46);
    Strip::set(frame, 2, k, 10);  // far from the reference, but outside the band
    Strip::set(frame, 5, k, 98);
  }
  Strip::set(frame, 3, 1, 97);
  const ContactErrors e = contactErrors(s.reference, frame, s.unshadowed, s.background, region, 1);
  EXPECT_EQ(e.bandPixels, 1u);
  EXPECT_EQ(e.meanAbs, 6.0);
  EXPECT_EQ(e.meanSigned, 6.0);
  EXPECT_EQ(e.spuriousPixels, 1u);

  // Radius 2 reaches pixel 2: (6 + 40) / 2 abs, (6 - 40) / 2 signed.
  const ContactErrors wide =
      contactErrors(s.reference, frame, s.unshadowed, s.background, region, 2);
  EXPECT_EQ(wide.bandPixels, 2u);
  EXPECT_EQ(wide.meanAbs, 23.0);
  EXPECT_EQ(wide.meanSigned, -17.0);
}

TEST(ShadowRegion, EmptyBandGivesZeroErrors) {
  Strip s;
  const core::Image8 region = shadowRegion(s.reference, s.unshadowed, s.background, "region");
  const ContactErrors e =
      contactErrors(s.reference, s.unshadowed, s.unshadowed, s.background, region, 3);
  EXPECT_EQ(e.bandPixels, 0u);
  EXPECT_EQ(e.spuriousPixels, 0u);
  EXPECT_EQ(e.meanAbs, 0.0);
  EXPECT_EQ(e.meanSigned, 0.0);
}

}  // namespace
}  // namespace penumbra::reference
