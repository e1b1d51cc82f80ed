// The shadow region the accuracy numbers are measured over (design §4, docs/accuracy.md),
// and the contact errors at its edge with the product (docs/failure-regimes.md).
//
// One rule, used by `penumbra accuracy` and the accuracy sweep (bench/accuracy_sweep.cpp)
// whenever no mask file is given: a pixel is in the shadow region when
//   * it is not a product pixel (the shadow-free frame — background + product, zero passes —
//     differs from the background there), and
//   * the reference differs from the shadow-free frame by at least one level in some channel
//     ("where the product's shadow changes a byte").
// This is the rule the ray-traced reference applies to its own mask
// (reference/differential.h: pixels without product samples whose bytes differ from the
// background) and the one docs/accuracy.md states ("product pixels excluded"). The two
// earlier copies both kept the product's pixels whenever the reference shaded the product
// differently from Penumbra (the product is an error of its own, not the shadow's), and the
// sweep's copy also took a threshold other than one level, so the two could name different
// regions for the same frames.
//
// Images are RGBA8 as Penumbra renders them (alpha ignored) or core::Image8; all
// must share one size (MetricsError otherwise). Cost: one pass over the pixels, and for the
// contact band one (2 radius + 1)^2 dilation per product pixel.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/image.h"
#include "reference/image_metrics.h"

namespace penumbra::reference {

// 1 where the shadow-free frame differs from the background in some channel: the pixels the
// product itself covers. `unshadowed` and `background` are RGBA8 of width x height.
std::vector<uint8_t> productPixels(std::span<const uint8_t> unshadowed,
                                   std::span<const uint8_t> background, uint32_t width,
                                   uint32_t height);

// The shadow region of `reference` (the rule above), named `name`.
core::Image8 shadowRegion(const core::Image8& reference, std::span<const uint8_t> unshadowed,
                          std::span<const uint8_t> background, std::string name);

// Clears from `region` (a mask given as a file, or the ray tracer's, which leaves out the
// reference's product pixels only) the pixels the product covers in the shadow-free frame:
// the region rule above, applied to any mask.
void excludeProductPixels(core::Image8& region, std::span<const uint8_t> unshadowed,
                          std::span<const uint8_t> background);

// Shadow acne and light leaking at contact, against the reference: the contact band is the
// shadow region within `radius` pixels (Chebyshev distance) of the product's pixels (where
// it meets the floor); its signed mean error > 0 means the frame is too light there (light
// leaking under the product). Spurious shadow counts pixels outside the shadow region and
// the product that the frame darkens by 3 levels or more from the shadow-free frame (acne,
// or shadow where none falls).
struct ContactErrors {
  uint64_t bandPixels = 0, spuriousPixels = 0;
  double meanAbs = 0, meanSigned = 0;  // per channel sample over the band; 0 when it is empty
};

ContactErrors contactErrors(const core::Image8& reference, std::span<const uint8_t> frame,
                            std::span<const uint8_t> unshadowed,
                            std::span<const uint8_t> background, const core::Image8& region,
                            int radius);

}  // namespace penumbra::reference
