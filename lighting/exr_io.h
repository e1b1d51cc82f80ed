// OpenEXR in and out for radiance images (light probes, merged brackets). Built with
// PENUMBRA_WITH_OPENEXR. Errors throw HdrError naming the file.
#pragma once

#include <cstddef>
#include <filesystem>

#include "core/image.h"
#include "lighting/exr_header.h"
#include "lighting/hdr_image.h"

namespace penumbra::lighting {

struct ExrReadReport {
  // Negative values set to 0. Lossy compression (DWAA/DWAB, as in Blender's studio-light
  // probes) rings around bright edges into small negative radiance, which is not physical
  // and would break logarithms and importance sampling downstream.
  size_t clampedNegative = 0;
  float mostNegative = 0;  // the smallest value clamped (0 if none)
};

// Reads the R, G, B channels (any pixel type; a luminance-only "Y" file is replicated to
// RGB) of the data window, after readExrLayout (exr_header.h) has passed the header. Rejects NaN
// and infinite values (counting them in the message).
core::ImageF readExr(const std::filesystem::path& path, ExrReadReport* report = nullptr);

// How writeExr stores the samples. Half (binary16: 11 significant bits, up to 65504) is what
// HDR video and light probes are usually kept in, at half the bytes; it rounds each value to
// the nearest half, so it is for images that are data (a camera's frames), not for results
// that must read back bit for bit.
enum class ExrPixels { Float, Half };

// Writes R, G, B (32-bit float by default) with lossless ZIP compression (for half frames, 8%
// smaller than PIZ on interior.exr photographed by `penumbra envmap-sequence`: 4.30 against
// 4.66 MB for 48 frames of 160²). Throws for an empty or inconsistent image, a non-finite
// value, or, as half, a value beyond ±65504 (it would become infinite); on error no file is
// left behind.
void writeExr(const std::filesystem::path& path, const core::ImageF& image,
              ExrPixels pixels = ExrPixels::Float);

}  // namespace penumbra::lighting
