// LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild 2020, "FLIP: A
// Difference Evaluator for Alternating Images", HPG 2020), written from the paper's
// description: a per-pixel perceptual difference in [0, 1] between a reference and a test
// image as a viewer flipping between them would see it (tutorial §8.2: metrics that model the
// eye, not the bytes).
//
// Pipeline (paper §4–5):
//  1. colour: sRGB → linear RGB → XYZ (D65) → YyCxCz (opponent space, linear in XYZ);
//  2. spatial filtering by the contrast sensitivity functions of the three channels, each a
//     sum of Gaussians in visual degrees (§4.1), clamp-to-edge borders; back to linear RGB,
//     clamped to [0, 1], then to CIELAB;
//  3. Hunt adjustment (a, b scaled by L/100) and the HyAB distance |ΔL| + ‖Δ(a, b)‖, raised to
//     q_c = 0.7 and compressed by the green–blue maximum with p_c = 0.4, p_t = 0.95 (§4.2);
//  4. features on the achromatic channel: edges (first derivative of a Gaussian) and points
//     (second derivative), σ = 0.5 · 0.082° · PPD, difference of magnitudes, scaled by 1/√2
//     and raised to q_f = 0.5 (§4.3);
//  5. ΔE = ΔE_c^(1 − ΔE_f) (§4.4).
//
// Viewing condition: `pixelsPerDegree` — the paper's default 67.0 (a 0.7 m wide 3840-pixel
// monitor seen from 0.7 m). The kiosk's 640×480 frames seen on a ~0.3 m wide screen from
// 0.6 m would be ~11 PPD; the default keeps numbers comparable with published FLIP values.
//
// Not per-frame code: double precision, libm (exp, pow, cbrt, sqrt). Cost: separable
// filters, O(width·height·(r_csf + r_feature)) with radii ~ PPD/4 and ~PPD/12.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra::reference {

struct FlipOptions {
  double pixelsPerDegree = 67.0;  // paper §5 default
};

// Per-pixel LDR-FLIP between `reference` and `test`, both RGB8 (3 bytes per pixel, rows top
// first, sRGB-encoded), width × height. Returns width·height values in [0, 1]. Throws
// std::invalid_argument on a size mismatch or an empty image.
std::vector<float> flipErrorMap(std::span<const uint8_t> reference, std::span<const uint8_t> test,
                                uint32_t width, uint32_t height, const FlipOptions& options = {});

}  // namespace penumbra::reference
