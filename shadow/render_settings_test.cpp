#include "shadow/render_settings.h"

#include <gtest/gtest.h>

#include "shadow/frame_compositor.h"

namespace penumbra::shadow {
namespace {

TEST(RenderSettings, DefaultsAreTheCompositorsAndTheKiosksLadder) {
  const RenderSettings s;
  EXPECT_NO_THROW(validateRenderSettings(s));
  EXPECT_FALSE(s.tuned);
  const CompositorOptions c = compositorOptions(s), d;
  EXPECT_EQ(c.shadowMapSize, d.shadowMapSize);
  EXPECT_EQ(c.fineProxyPasses, d.fineProxyPasses);
  EXPECT_EQ(c.areaPenumbrae, d.areaPenumbrae);
  EXPECT_EQ(c.shafts.pruneFraction, d.shafts.pruneFraction);
  EXPECT_EQ(c.shafts.maxReceiversPerLeaf, d.shafts.maxReceiversPerLeaf);
  EXPECT_EQ(shadowMapLadder(s), (std::vector<uint32_t>{256, 128, 64}));
}

TEST(RenderSettings, SettingsReachTheCompositor) {
  const CompositorOptions c = compositorOptions({20, 512, 4, false, true, 0.05, 16});
  EXPECT_EQ(c.shadowMapSize, 512u);
  EXPECT_EQ(c.fineProxyPasses, 4u);
  EXPECT_FALSE(c.areaPenumbrae);
  EXPECT_EQ(c.shafts.pruneFraction, 0.05);
  EXPECT_EQ(c.shafts.maxReceiversPerLeaf, 16u);
  EXPECT_TRUE(c.productFineProxyPasses.empty());
  EXPECT_EQ(compositorOptions({64, 256, 16, true, false, 0.02, 8, {50, 8}}).productFineProxyPasses,
            (std::vector<uint32_t>{50, 8}));
}

// A product's own count where the settings have one per product, the shared one otherwise.
TEST(RenderSettings, FineProxyPassesPerProduct) {
  RenderSettings s;
  EXPECT_EQ(fineProxyPassesOf(s, 0), 16u);
  EXPECT_EQ(fineProxyPassesOf(s, 5), 16u);
  s.productFineProxyPasses = {0, 50, 8};
  EXPECT_EQ(fineProxyPassesOf(s, 0), 0u);
  EXPECT_EQ(fineProxyPassesOf(s, 1), 50u);
  EXPECT_EQ(fineProxyPassesOf(s, 2), 8u);
  EXPECT_NO_THROW(validateRenderSettings(s, 3));
  EXPECT_THROW(validateRenderSettings(s, 2), std::invalid_argument);
  s.productFineProxyPasses.clear();
  EXPECT_NO_THROW(validateRenderSettings(s, 2));
}

// Every valid map size gives three strictly decreasing multiples of 16 of at least 16: what
// the frame-rate controller and the renderer accept.
TEST(RenderSettings, LadderRungsAreValidMapSizes) {
  for (uint32_t size = 64; size <= 4096; size += 16) {
    RenderSettings s;
    s.shadowMapSize = size;
    ASSERT_NO_THROW(validateRenderSettings(s));
    const std::vector<uint32_t> ladder = shadowMapLadder(s);
    ASSERT_EQ(ladder.size(), 3u);
    EXPECT_EQ(ladder[0], size);
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(ladder[i] % 16, 0u) << size;
      EXPECT_GE(ladder[i], 16u) << size;
      if (i > 0) {
        EXPECT_LT(ladder[i], ladder[i - 1]) << size;
      }
    }
  }
  EXPECT_EQ(shadowMapLadder({64, 96, 16, true, false}), (std::vector<uint32_t>{96, 48, 16}));
}

TEST(RenderSettings, InvalidSettingsAreNamed) {
  const auto why = [](const RenderSettings& s) -> std::string {
    try {
      validateRenderSettings(s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(why({258, 256, 16, true, false}), "settings.max_passes: 258 is not in [1, 257]");
  EXPECT_EQ(why({64, 48, 16, true, false}),
            "settings.shadow_map_size: 48 is not a multiple of 16 in [64, 4096]");
  EXPECT_EQ(why({64, 4112, 16, true, false}),
            "settings.shadow_map_size: 4112 is not a multiple of 16 in [64, 4096]");
  EXPECT_EQ(why({64, 256, 16, true, false, -0.01, 8}),
            "settings.prune_fraction: -0.01 is not in [0, 0.25]");
  EXPECT_EQ(why({64, 256, 16, true, false, 0.02, 65}),
            "settings.receivers_per_leaf: 65 is not in [1, 64]");
  EXPECT_EQ(why({64, 256, 16, true, false, 0, 1}), "accepted");
  EXPECT_EQ(why({64, 256, 16, true, false}), "accepted");
  EXPECT_EQ(why({64, 256, 16, true, false, 0.02, 8, {0, 258}}),
            "settings.product_fine_proxy_passes[1]: 258 is more than 257");
  EXPECT_EQ(why({64, 256, 16, true, false, 0.02, 8, {257, 0}}), "accepted");
}

}  // namespace
}  // namespace penumbra::shadow
