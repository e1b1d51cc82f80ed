// Writing 8-bit frames as PNG through libpng (when built with it). Errors name the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/error.h"

namespace penumbra::scene {

class ImageError : public core::Error {
 public:
  using core::Error::Error;
};

// Writes RGBA8 pixels (row 0 at the top) as a PNG; throws ImageError.
void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height,
              std::span<const uint8_t> rgba);

}  // namespace penumbra::scene
