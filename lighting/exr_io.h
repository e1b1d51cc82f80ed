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

// Writes 32-bit float R, G, B with lossless ZIP compression. Throws for an empty or
// inconsistent image or a non-finite value; on error no file is left behind.
void writeExr(const std::filesystem::path& path, const core::ImageF& image);

}  // namespace penumbra::lighting
