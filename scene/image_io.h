// 8-bit image files: PNG through libpng (when built with it). Errors name the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <vector>

namespace penumbra::scene {

class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ImageRgba8 {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> pixels;  // RGBA, row 0 at the top
};

bool pngSupported();

// Writes RGBA8 pixels (row 0 at the top) as a PNG; throws ImageError.
void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height,
              std::span<const uint8_t> rgba);

// Reads any PNG as RGBA8; throws ImageError.
ImageRgba8 readPng(const std::filesystem::path& path);

}  // namespace penumbra::scene
