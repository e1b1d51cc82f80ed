// The per-frame settings a scene bundle carries (issue 17): how many passes a frame may
// draw, how large its shadow maps are, how many passes draw the fine proxy, whether the
// passes spread their edges over area-light penumbrae. `penumbra precompute` writes the
// defaults; a tuned bundle carries what its scene needs. `penumbra render`, `profile`,
// `accuracy`, the kiosk and the simulator start from them, so the same bundle gives the
// same frames everywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace penumbra::shadow {

struct CompositorOptions;  // shadow/frame_compositor.h (which includes the bundle, so not here)

struct RenderSettings {
  // The pass ceiling (Gibson 2003 §8's frame-rate control picks at most this many; the
  // kiosk's own max_passes can only lower it).
  uint32_t maxPasses = 64;
  // The largest shadow map (§7.2); the kiosk's frame-rate fallbacks halve it twice.
  // The last three: CompositorOptions' defaults (a test holds them equal).
  uint32_t shadowMapSize = 256;
  uint32_t fineProxyPasses = 16;
  bool areaPenumbrae = true;
  // Chosen for this scene by `penumbra tune` rather than the defaults above.
  bool tuned = false;
  // The shaft hierarchy's (Gibson 2003 §6, shadow/shaft_hierarchy.h ShaftBuildOptions): the
  // share of a receiver's light below which a shaft is insignificant, pruned within that
  // budget per receiver vertex, and the receivers per octree leaf. Both move which receivers
  // each pass draws, so the board's cost model prices them through its shadowed pixels.
  // Bundle version 8; older bundles load with these defaults.
  double pruneFraction = 0.02;
  uint32_t receiversPerLeaf = 8;
  // Empty, or one per product: that product's fine-proxy passes in place of fineProxyPasses
  // (bundle version 9; a scene file's `fine_proxy_passes`). Products want opposite things: at
  // the desk corner (64-spp reference) the bunny's contact shadow rose from 50 to 64 passes
  // with 16 of 50 drawing its fine proxy (0.390 -> 0.471 levels) and falls with 32 (0.383 ->
  // 0.367), while the teapot's two lit contact pixels there need the coarse proxy in most
  // passes (p99 beyond the reference's bounds 9 with the fine one in all, 6 with 8 of 50).
  // docs/accuracy.md, "Fine-proxy passes per product".
  std::vector<uint32_t> productFineProxyPasses{};
  // A shadow map per source cluster (shadow/cluster_map_size.h): each point-light pass gets
  // this many texels per pixel of its shadow's footprint on screen, at most shadowMapSize;
  // 0 (the default): every pass at shadowMapSize, as Gibson 2003 §7.2. Bundle version 10.
  double texelsPerShadowPixel = 0;
  bool operator==(const RenderSettings&) const = default;
};

// The largest pass ceiling a bundle may carry (the renderer's own limit on passes).
inline constexpr uint32_t kMaxSettingsPasses = 257;
// A quarter of a receiver's light pruned unshadowed is no longer a shadow; leaves of more than
// 64 receivers are one shaft over most of a wall.
inline constexpr double kMaxPruneFraction = 0.25;
inline constexpr uint32_t kMaxReceiversPerLeaf = 64;
// More texels per footprint pixel than this only ever gives the frame's whole map.
inline constexpr double kMaxTexelsPerShadowPixel = 64;

// The fine-proxy passes product `product` is drawn with (stated at
// kFineProxyReferencePasses passes, shadow/pass_list.h): its own when the settings have one per
// product, else fineProxyPasses.
uint32_t fineProxyPassesOf(const RenderSettings& s, uint32_t product);
// The same rule on its two parts (CompositorOptions holds them too): perProduct[product] when
// perProduct has one per product, else `shared`.
uint32_t fineProxyPassesOf(uint32_t shared, std::span<const uint32_t> perProduct, uint32_t product);

// Throws std::invalid_argument naming the field: maxPasses in [1, kMaxSettingsPasses],
// shadowMapSize a multiple of 16 in [64, 4096] (its fallbacks stay multiples of 16),
// fineProxyPasses and each of productFineProxyPasses at most kMaxSettingsPasses, pruneFraction in
// [0, kMaxPruneFraction], receiversPerLeaf in [1, kMaxReceiversPerLeaf], texelsPerShadowPixel
// in [0, kMaxTexelsPerShadowPixel]; with `products` given,
// productFineProxyPasses empty or one per product.
void validateRenderSettings(const RenderSettings& s, std::optional<size_t> products = {});

// The compositor's options for these settings (everything else at its default).
CompositorOptions compositorOptions(const RenderSettings& s);

// The frame-rate controller's map sizes: shadowMapSize, then its half and its quarter
// (256: 256, 128, 64, the kiosk's ladder before settings existed).
std::vector<uint32_t> shadowMapLadder(const RenderSettings& s);

}  // namespace penumbra::shadow
