// Reading photographs (JPEG, PNG, TIFF… whatever OpenCV's imread decodes) as 8-bit RGB,
// for the capture pipeline: the bracketed exposures of lighting/hdr_merge.h take exactly
// this layout (core::Image8). Part of penumbra_calibration (PENUMBRA_WITH_OPENCV).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/image.h"

namespace penumbra::scene {

// Throws CalibrationError (scene/camera_intrinsics.h) naming the file when it is missing,
// cannot be decoded, or is not 8 bits per channel (a 16-bit TIFF would silently lose its
// range; convert it explicitly).
core::Image8 readPhotoRgb8(const std::filesystem::path& path);

}  // namespace penumbra::scene
