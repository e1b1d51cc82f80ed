// The real environment camera's 8-bit frames turned into linear radiance
// (platform/opencv_environment_camera.h). A webcam is not an HDR camera: its values go
// through a response curve — sRGB's (IEC 61966-2-1) or a plain gamma — which is inverted here
// by a table of 256 entries computed once, from IEEE arithmetic and envmap's portable log and
// exp (the same bits on every machine, design §3), and divided by the exposure scale.
//
// A value at or above kSaturatedValue in any channel is counted as saturated: the sensor
// clipped there, so a lamp that saturates is reported dimmer than it is and its light
// under-reports its power. That is the limit of single-exposure capture (Havran et al. 2005
// used an HDR camera, §5.1: eight orders of magnitude, "saturation-free images").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/image.h"

namespace penumbra::platform {

inline constexpr uint8_t kSaturatedValue = 250;

// The inverse response, value → linear radiance / exposureScale. `gamma` 0: the sRGB curve
// (v/255 ≤ 0.04045: c/12.92, else ((c + 0.055)/1.055)^2.4); otherwise (v/255)^gamma.
// Throws std::invalid_argument for a negative or non-finite gamma or a non-positive scale.
std::array<float, 256> inverseResponse(double gamma, double exposureScale);

// The sRGB encoding of a linear value in [0, 1], rounded to 8 bits (libm: for tests and
// synthetic footage, not the per-frame path).
uint8_t encodeSrgb8(double linear);

// One 8-bit BGR frame (OpenCV's order; rows `stride` bytes apart) into `out` (RGB, resized
// to width × height) through `table`. Returns the number of saturated pixels.
size_t linearise(const uint8_t* bgr, size_t stride, uint32_t width, uint32_t height,
                 const std::array<float, 256>& table, core::ImageF& out);

}  // namespace penumbra::platform
