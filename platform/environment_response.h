// The real environment camera's 8-bit frames turned into linear radiance
// (platform/opencv_environment_camera.h). A webcam is not an HDR camera: its values go
// through a response curve, which is inverted here by a table of 256 entries per channel
// computed once, from IEEE arithmetic and envmap's portable log and exp (the same bits on
// every machine, design §3), and divided by the exposure time and the exposure scale. The
// curve is sRGB's (IEC 61966-2-1), a plain gamma, or the camera's own: g(z) = ln(E·Δt)
// recovered from a bracket by Debevec & Malik 1997's solve (`penumbra camera-response`,
// kiosk/camera_response_file.h). A bracket of exposures is merged into HDR by
// platform/bracket_merge.h from the same tables.
//
// A value at or above kSaturatedValue in any channel of a single frame is counted as
// saturated: the sensor clipped there, so a lamp that saturates is reported dimmer than it
// is and its light under-reports its power. That is the limit of single-exposure capture
// (Havran et al. 2005 used an HDR camera, §5.1: eight orders of magnitude,
// "saturation-free images"), and what the bracket is for.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/image.h"
#include "kiosk/camera_response_file.h"

namespace penumbra::platform {

inline constexpr uint8_t kSaturatedValue = 250;

// The inverse response, value → linear radiance / exposureScale. `gamma` 0: the sRGB curve
// (v/255 ≤ 0.04045: c/12.92, else ((c + 0.055)/1.055)^2.4); otherwise (v/255)^gamma.
// Throws std::invalid_argument for a negative or non-finite gamma or a non-positive scale.
std::array<float, 256> inverseResponse(double gamma, double exposureScale);

// Per channel (R, G, B) and 8-bit code: the exposure E·Δt the camera records as that code
// (binary64, relative units), or, in a ChannelTables, the radiance a frame's code stands for.
using ChannelResponse = std::array<std::array<double, 256>, 3>;
using ChannelTables = std::array<std::array<float, 256>, 3>;

// The sRGB curve (gamma 0) or value^gamma, the same for the three channels (as
// inverseResponse before the division). Throws std::invalid_argument for a bad gamma.
ChannelResponse curveResponse(double gamma);

// A calibrated response, exp(g(z)) per channel by envmap::portableExp (not libm).
ChannelResponse calibratedResponse(const kiosk::CameraResponseCurves& curves);

// The radiance table of frames exposed for `exposureMs` (1 when the time is not known):
// response / exposureMs / exposureScale, in that order in binary64, rounded once to binary32.
// Throws std::invalid_argument for a non-positive or non-finite time or scale.
ChannelTables radianceTables(const ChannelResponse& response, double exposureMs,
                             double exposureScale);

// The sRGB encoding of a linear value in [0, 1], rounded to 8 bits (libm: for tests and
// synthetic footage, not the per-frame path).
uint8_t encodeSrgb8(double linear);

// One 8-bit BGR frame (OpenCV's order; rows `stride` bytes apart) into `out` (RGB, resized
// to width × height) through `tables` (R, G, B). Returns the number of saturated pixels.
size_t linearise(const uint8_t* bgr, size_t stride, uint32_t width, uint32_t height,
                 const ChannelTables& tables, core::ImageF& out);

}  // namespace penumbra::platform
