// Image types of the HDR capture (Gibson & Chalmers 2003 §4): bracketed 8-bit exposures in,
// float radiance out. Plain structs without any library type, so penumbra_hdr stays free of
// OpenCV; callers load photographs however they like (the calibrate/capture commands use
// OpenCV's imread).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"

namespace penumbra::lighting {

class HdrError : public core::Error {
 public:
  using core::Error::Error;
};

// 8-bit RGB, 3 bytes per pixel, rows top to bottom.
struct Ldr8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

// One photograph of a bracket and its exposure time (seconds, or any unit common to the
// bracket: only ratios matter).
struct Exposure {
  std::string name;  // for messages, e.g. the file name
  double seconds = 0;
  Ldr8Image image;
};

// Linear radiance (relative units), 3 floats per pixel, rows top to bottom.
struct HdrImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  const float* pixel(uint32_t x, uint32_t y) const { return &rgb[index(x, y)]; }
  float* pixel(uint32_t x, uint32_t y) { return &rgb[index(x, y)]; }

 private:
  size_t index(uint32_t x, uint32_t y) const { return (size_t{y} * size_t(width) + x) * 3; }
};

}  // namespace penumbra::lighting
