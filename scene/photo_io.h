// Reading photographs (JPEG, PNG, TIFF… whatever OpenCV's imread decodes) as 8-bit RGB,
// for the capture pipeline: the bracketed exposures of lighting/hdr_merge.h take exactly
// this layout (lighting::Ldr8Image). Part of penumbra_calibration (PENUMBRA_WITH_OPENCV).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace penumbra::scene {

struct PhotoRgb8 {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 3 bytes per pixel (R, G, B), rows top to bottom
};

// Throws CalibrationError (scene/camera_intrinsics.h) naming the file when it is missing,
// cannot be decoded, or is not 8 bits per channel (a 16-bit TIFF would silently lose its
// range; convert it explicitly).
PhotoRgb8 readPhotoRgb8(const std::filesystem::path& path);

}  // namespace penumbra::scene
