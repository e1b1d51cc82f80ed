// Bracketed 8-bit exposures -> one radiance image through a recovered camera response
// (Debevec & Malik 1997 eq. 6; Gibson & Chalmers 2003 §4):
//   ln E = sum_j w(Z_j) (g(Z_j) - ln dt_j) / sum_j w(Z_j),   w = hatWeight (0 at 0 and 255)
// OpenCV's MergeDebevec gives clipped codes weight 1, so a pixel clipped in one exposure
// still pulls the average; here a clipped code contributes nothing. A pixel clipped in
// every exposure has no estimate: it gets the bound of the nearest unclipped code (code
// 254 in the shortest exposure when bright, code 1 in the longest when dark) and is counted.
// Offline only (libm).
#pragma once

#include <cstddef>
#include <span>

#include "lighting/camera_response.h"
#include "lighting/hdr_image.h"

namespace penumbra::lighting {

struct MergeResult {
  core::ImageF radiance;  // relative radiance, exposure time 1 (g(128) = 0 units)
  // Pixels with a channel clipped in every exposure (weight 0 throughout), by whether the
  // shortest exposure shows it bright (>= 128, i.e. 255: saturated) or dark (code 0).
  size_t clippedBright = 0;
  size_t clippedDark = 0;
  double minRadiance = 0, maxRadiance = 0;  // over unclipped channel values (dynamic range)
};

// Throws HdrError for an invalid bracket (checkBracket).
MergeResult mergeExposures(std::span<const Exposure> bracket, const CameraResponse& response);

}  // namespace penumbra::lighting
