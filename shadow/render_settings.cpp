#include "shadow/render_settings.h"

#include "core/json_reader.h"
#include "shadow/frame_compositor.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace penumbra::shadow {

uint32_t fineProxyPassesOf(uint32_t shared, std::span<const uint32_t> perProduct,
                           uint32_t product) {
  return product < perProduct.size() ? perProduct[product] : shared;
}

uint32_t fineProxyPassesOf(const RenderSettings& s, uint32_t product) {
  return fineProxyPassesOf(s.fineProxyPasses, s.productFineProxyPasses, product);
}

void validateRenderSettings(const RenderSettings& s, std::optional<size_t> products) {
  const auto bad = [](const std::string& field, const std::string& why) {
    throw std::invalid_argument("settings." + field + ": " + why);
  };
  if (s.maxPasses < 1 || s.maxPasses > kMaxSettingsPasses) {
    bad("max_passes",
        std::to_string(s.maxPasses) + " is not in [1, " + std::to_string(kMaxSettingsPasses) + "]");
  }
  if (s.shadowMapSize < 64 || s.shadowMapSize > 4096 || s.shadowMapSize % 16 != 0) {
    bad("shadow_map_size",
        std::to_string(s.shadowMapSize) + " is not a multiple of 16 in [64, 4096]");
  }
  if (s.fineProxyPasses > kMaxSettingsPasses) {
    bad("fine_proxy_passes",
        std::to_string(s.fineProxyPasses) + " is more than " + std::to_string(kMaxSettingsPasses));
  }
  for (size_t i = 0; i < s.productFineProxyPasses.size(); ++i) {
    if (s.productFineProxyPasses[i] > kMaxSettingsPasses) {
      bad("product_fine_proxy_passes[" + std::to_string(i) + "]",
          std::to_string(s.productFineProxyPasses[i]) + " is more than " +
              std::to_string(kMaxSettingsPasses));
    }
  }
  if (products && !s.productFineProxyPasses.empty() &&
      s.productFineProxyPasses.size() != *products) {
    bad("product_fine_proxy_passes", std::to_string(s.productFineProxyPasses.size()) +
                                         " values for " + std::to_string(*products) + " products");
  }
  if (!(s.pruneFraction >= 0 && s.pruneFraction <= kMaxPruneFraction)) {
    bad("prune_fraction", core::formatNumber(s.pruneFraction) + " is not in [0, " +
                              core::formatNumber(kMaxPruneFraction) + "]");
  }
  if (s.receiversPerLeaf < 1 || s.receiversPerLeaf > kMaxReceiversPerLeaf) {
    bad("receivers_per_leaf", std::to_string(s.receiversPerLeaf) + " is not in [1, " +
                                  std::to_string(kMaxReceiversPerLeaf) + "]");
  }
  if (!(s.texelsPerShadowPixel >= 0 && s.texelsPerShadowPixel <= kMaxTexelsPerShadowPixel)) {
    bad("texels_per_shadow_pixel", core::formatNumber(s.texelsPerShadowPixel) + " is not in [0, " +
                                       core::formatNumber(kMaxTexelsPerShadowPixel) + "]");
  }
}

CompositorOptions compositorOptions(const RenderSettings& s) {
  CompositorOptions c;
  c.shadowMapSize = s.shadowMapSize;
  c.fineProxyPasses = s.fineProxyPasses;
  c.productFineProxyPasses = s.productFineProxyPasses;
  c.areaPenumbrae = s.areaPenumbrae;
  c.texelsPerShadowPixel = s.texelsPerShadowPixel;
  c.shafts.pruneFraction = s.pruneFraction;
  c.shafts.maxReceiversPerLeaf = s.receiversPerLeaf;
  return c;
}

std::vector<uint32_t> shadowMapLadder(const RenderSettings& s) {
  // Halving a multiple of 16 that is at least 64 twice leaves a multiple of 4 of at least
  // 16: rounded down to 16, the rungs stay valid map sizes and strictly decreasing.
  const auto rung = [](uint32_t size) { return std::max(16u, size / 16 * 16); };
  return {s.shadowMapSize, rung(s.shadowMapSize / 2), rung(s.shadowMapSize / 4)};
}

}  // namespace penumbra::shadow
