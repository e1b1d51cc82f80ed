// The project's two image types: Image8 (8-bit samples: photographs, rendered frames
// converted to RGB, masks) and ImageF (float RGB radiance: the HDR merge of Debevec & Malik
// 1997 as used by Gibson & Chalmers 2003 §4, EXR files, light probes). Plain structs without
// any library type, so every layer can use them and each reader (OpenCV, OpenEXR) stays in
// the file that reads.
//
// Layout (both): row-major, rows top to bottom, `channels` interleaved samples per pixel;
// sample c of pixel (x, y) is at (y·width + x)·channels + c. Nothing here checks a size on
// access: callers that take images from outside check `hasExpectedSize()` once and throw
// their own error type naming the image.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::core {

// 8 bits per sample. channels is 3 for RGB (R, G, B order) and 1 for a mask or grey image
// (mask convention: nonzero = inside).
struct Image8 {
  uint32_t width = 0, height = 0;
  uint32_t channels = 3;
  std::vector<uint8_t> pixels;
  std::string name;  // file it came from, or a label: for error messages only

  Image8() = default;
  // A width × height image with every sample set to `fill`.
  Image8(uint32_t w, uint32_t h, uint32_t c, std::string label, uint8_t fill = 0)
      : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill), name(std::move(label)) {}

  size_t pixelCount() const { return size_t(width) * height; }
  // True when `pixels` holds exactly width·height·channels samples.
  bool hasExpectedSize() const { return pixels.size() == pixelCount() * channels; }
  const uint8_t* pixel(uint32_t x, uint32_t y) const { return &pixels[index(x, y)]; }
  uint8_t* pixel(uint32_t x, uint32_t y) { return &pixels[index(x, y)]; }

 private:
  size_t index(uint32_t x, uint32_t y) const { return (size_t{y} * width + x) * channels; }
};

// Linear radiance (relative units), 3 floats per pixel (R, G, B).
struct ImageF {
  static constexpr uint32_t channels = 3;
  uint32_t width = 0, height = 0;
  std::vector<float> pixels;

  ImageF() = default;
  // A width × height image with every sample set to `fill`.
  ImageF(uint32_t w, uint32_t h, float fill = 0.0f)
      : width(w), height(h), pixels(size_t(w) * h * channels, fill) {}

  size_t pixelCount() const { return size_t(width) * height; }
  bool hasExpectedSize() const { return pixels.size() == pixelCount() * channels; }
  const float* pixel(uint32_t x, uint32_t y) const { return &pixels[index(x, y)]; }
  float* pixel(uint32_t x, uint32_t y) { return &pixels[index(x, y)]; }

 private:
  size_t index(uint32_t x, uint32_t y) const { return (size_t{y} * width + x) * channels; }
};

}  // namespace penumbra::core
