// A minimal HDR image reader/writer for light probes (Gibson & Chalmers 2003 §4.2): float RGB
// from OpenEXR files (any compression OpenEXR decodes, e.g. the DWAB of Blender's CC0
// studio lights). Kept in its own file so it can be merged with a project-wide EXR module.
// Built only with PENUMBRA_WITH_OPENEXR (PENUMBRA_HAVE_OPENEXR defined).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace penumbra::lighting {

class ProbeImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Linear radiance, RGB interleaved, row-major with row 0 at the top.
struct ProbeImage {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // 3 * width * height
  const float* pixel(uint32_t x, uint32_t y) const { return &rgb[(size_t{y} * width + x) * 3]; }
  float* pixel(uint32_t x, uint32_t y) { return &rgb[(size_t{y} * width + x) * 3]; }
};

#ifdef PENUMBRA_HAVE_OPENEXR
// Reads the R, G, B channels of the data window (a missing channel reads as 0; a file with
// none of them is an error). Throws ProbeImageError "FILE: what" for unreadable, corrupt or
// empty files.
ProbeImage readExrProbe(const std::filesystem::path& path);
// Writes a 32-bit float RGB EXR (ZIP). Throws ProbeImageError naming the file.
void writeExrProbe(const ProbeImage& image, const std::filesystem::path& path);
#endif

}  // namespace penumbra::lighting
