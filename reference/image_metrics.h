// Image-quality metrics for Penumbra's accuracy work (design §4, tutorial §8.2): how far a
// rendered frame is from a reference, in 8-bit units, in PSNR, in SSIM, and perceptually
// (LDR-FLIP, reference/flip.h) — over the whole frame and inside a mask (the shadow region).
//
// Definitions (all over RGB8 images of equal size; a "sample" is one channel of one pixel):
//  - abs error e = |a − b| per sample, an integer 0..255;
//  - mean_abs: Σe / (3 · pixels); max_abs: the largest e;
//  - p99_abs: the nearest-rank 99th percentile of the 3·pixels samples e: the smallest value
//    v such that at least 99% of the samples are ≤ v (sorted ascending, index ⌈0.99·N⌉ − 1);
//  - psnr: 10·log10(255² / MSE), MSE over the same samples; +infinity when MSE = 0 (JSON:
//    null, with "identical": true);
//  - flip_mean: the mean of the per-pixel FLIP map (0 = indistinguishable, 1 = maximal);
//  - ssim (whole frame only): OpenCV contrib QualitySSIM on the 8-bit images (its constants
//    C1 = (0.01·255)², C2 = (0.03·255)² assume the 0–255 range; 11×11 Gaussian window,
//    σ = 1.5), the mean of the three channel means; ssim_masked: the mean of its per-pixel
//    SSIM map (averaged over channels) at the mask's pixels.
// A mask is an 8-bit image of the same size: nonzero = inside. A mask with no pixel inside
// gives region statistics with pixels = 0 and null values in JSON.
//
// Needs OpenCV (core imgproc imgcodecs quality): library penumbra_metrics,
// PENUMBRA_WITH_OPENCV.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"
#include "reference/flip.h"

namespace penumbra::reference {

// Bad input: unreadable or mismatched files. The message names the file and the problem.
class MetricsError : public core::Error {
 public:
  using core::Error::Error;
};

// Images are core::Image8: RGB with 3 channels, masks with 1 channel (nonzero = inside).

// Reads PNG (or anything OpenCV decodes) as 8-bit RGB; alpha is dropped, 16-bit input is
// scaled to 8 bits by OpenCV, grey is expanded. Throws MetricsError naming the file.
core::Image8 loadRgb8(const std::filesystem::path& path);
// Reads a mask (1 channel); colour masks are converted to grey first. Throws MetricsError.
core::Image8 loadMask(const std::filesystem::path& path);
// RGBA8 pixels (as Penumbra renders them) to a 3-channel core::Image8.
core::Image8 fromRgba8(std::span<const uint8_t> rgba, uint32_t width, uint32_t height,
                       std::string name);

struct RegionErrors {
  uint64_t pixels = 0;  // pixels in the region
  double meanAbs = 0;
  uint32_t p99Abs = 0;
  uint32_t maxAbs = 0;
  double psnr = 0;  // +infinity when the region is identical
  double flipMean = 0;
};

struct ImageComparison {
  uint32_t width = 0, height = 0;
  RegionErrors frame;
  std::optional<RegionErrors> masked;  // present when a mask was given
  double ssim = 1;                     // whole frame, mean over channels
  std::optional<double> ssimMasked;    // mean SSIM-map value inside the mask
  std::vector<float> flipMap;          // width·height, in [0, 1]
  double pixelsPerDegree = 0;          // the FLIP viewing condition used
};

struct CompareOptions {
  FlipOptions flip;
  bool computeFlip = true;  // FLIP costs ~100x the other metrics; a sweep may skip it
};

// Compares `test` against `reference`. Throws MetricsError (naming both images) when sizes
// differ, or when the mask's size differs from theirs.
ImageComparison compareImages(const core::Image8& reference, const core::Image8& test,
                              const core::Image8* mask = nullptr,
                              const CompareOptions& options = {});

// Errors against a reference known only to lie between `lower` and `upper` in each sample
// (the differential reference where the photograph's 8 bits leave it open,
// reference/differential.h): e = max(0, lower − v, v − upper), then mean_abs, p99_abs,
// max_abs and psnr as above over the mask's samples (flip_mean 0: FLIP has no interval
// form). Throws MetricsError (naming the images) when sizes differ or lower > upper in a
// sample.
RegionErrors intervalErrors(const core::Image8& lower, const core::Image8& upper,
                            const core::Image8& test, const core::Image8& mask);

// The comparison as a JSON object (field names as in the definitions above, "frame" and
// "mask" sub-objects, "ssim", "ssim_mask", "flip_ppd", "width", "height").
nlohmann::json toJson(const ImageComparison& c);

// Writes an error map in [0, 1] (e.g. the FLIP map) as an RGB PNG through a magma-like colour
// map (black-purple for 0 … pale yellow for 1). Throws MetricsError naming the file.
void writeHeatmapPng(const std::filesystem::path& path, std::span<const float> map, uint32_t width,
                     uint32_t height);
// The colour the heat map gives to value v (clamped to [0, 1]).
std::array<uint8_t, 3> heatmapColour(float v);

}  // namespace penumbra::reference
