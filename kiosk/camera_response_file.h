// The environment camera's calibrated response as a file (issue 16 item 1): per channel the
// 256 values g(z) = ln(E·Δt) of Debevec & Malik 1997 — the log exposure the camera records as
// the 8-bit code z — recovered offline from a bracket by `penumbra camera-response`
// (lighting::recoverResponse) and read by the board ("environment": {"response": FILE},
// kiosk_config.h). The kiosk does not link the offline solver (lighting/ is not on the board);
// this small JSON file is what passes between them:
//
//   {"format": "penumbra-camera-response", "version": 1,
//    "log_exposure": {"r": [256 numbers], "g": [...], "b": [...]},
//    "bracket": [{"image": "e250.png", "exposure_us": 250}, ...],   (where it came from)
//    "warnings": ["channel R: response not monotone at 2 code(s), ..."]}
//
// g is relative (the solve fixes g(128) = 0 per channel) and non-decreasing: the merge and
// the single-frame linearisation (platform/environment_response.h) need a response that
// maps a larger code to at least as much light. Numbers are written with 17 significant
// digits, so a curve reads back bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/regular_file.h"

namespace penumbra::kiosk {

inline constexpr std::string_view kCameraResponseFormat = "penumbra-camera-response";
inline constexpr int64_t kCameraResponseVersion = 1;
// |g| beyond this is not a camera: e^60 ≈ 1.1e26, so exp(g) / Δt / scale stays finite in
// binary32 for every exposure time and exposure_scale the configuration allows
// (Δt ≥ 1 µs = 1e-3 ms, scale ≥ 1e-6: at most 1.1e35 < 3.4e38).
inline constexpr double kMostLogExposure = 60;

struct CameraResponseCurves {
  std::array<std::array<double, 256>, 3> logExposure{};  // g(z) for R, G, B
  struct Shot {
    std::string image;
    int64_t exposureUs = 0;
  };
  std::vector<Shot> bracket;          // the bracket it was recovered from (for the reader)
  std::vector<std::string> warnings;  // the solver's (repaired codes)
};

// Why `g` cannot be used ("" when it can): a value that is not finite, beyond
// ±kMostLogExposure, smaller than the one before (naming the channel and the code), or a
// channel with g(255) = g(0) (it records no change of light).
std::string checkLogExposure(const std::array<std::array<double, 256>, 3>& g);

// Writes `curves` to `path` (the format above). Throws core::Error naming the file when the
// curves fail checkLogExposure or the file cannot be written.
void writeCameraResponse(const std::filesystem::path& path, const CameraResponseCurves& curves);

// Reads a file written by writeCameraResponse. Throws through `raise` naming the file and the
// field: not JSON, another format or version, an array that is not 256 numbers, or curves that
// fail checkLogExposure.
CameraResponseCurves readCameraResponse(const std::filesystem::path& path,
                                        core::ErrorThrower raise);

}  // namespace penumbra::kiosk
