// Inputs of the HDR capture (Gibson & Chalmers 2003 §4): bracketed 8-bit exposures
// (core::Image8, RGB) in, float radiance (core::ImageF) out. The image types carry no library
// type, so penumbra_hdr stays free of OpenCV; callers load photographs however they like (the
// calibrate/capture commands use scene::readPhotoRgb8).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace penumbra::lighting {

class HdrError : public core::Error {
 public:
  using core::Error::Error;
};

// One photograph of a bracket and its exposure time (seconds, or any unit common to the
// bracket: only ratios matter).
struct Exposure {
  std::string name;  // for messages, e.g. the file name
  double seconds = 0;
  core::Image8 image;
};

}  // namespace penumbra::lighting
