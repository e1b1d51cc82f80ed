// HDR from a bracket of 8-bit frames, per environment frame (issue 16 item 1; Debevec & Malik
// 1997 §2.2, eq. 6 in its linear form): the environment camera cycles through n exposure
// times, and each new frame is merged with the newest frame of every other time (a sliding
// window, platform/opencv_environment_camera.h). Per pixel and channel, with z_j the code of
// exposure j (Δt_j, shortest first) and the hat weight w(z) = min(z, 255 − z) of the solve
// (lighting/camera_response.h, which recovered the response these tables come from):
//
//   E = Σ_j w(z_j) · R_j(z_j) / Σ_j w(z_j),   R_j(z) = exp(g(z)) / Δt_j / exposure_scale.
//
// A code of 0 or 255 has weight 0: it says only that the light was below or above what that
// exposure records. Where every exposure is clipped, E is a bound, not an estimate: the
// shortest exposure's R_0(255) when it is saturated there (the pixel is counted as saturated:
// its light is under-reported), otherwise the longest exposure's value for its code.
//
// Bit-exact (design §3): R_j and w(z)·R_j(z) are binary32 tables computed once, from the
// portable exp (environment_response.h), not libm; per pixel only table lookups, binary32
// additions in exposure order (shortest first) and one division, with no FMA contraction
// (-ffp-contract=off). So a bracket gives the same bytes on every machine. Cost per pixel:
// 3 · n lookups of each table, 3 · 2n additions, 3 divisions; three 480 × 480 exposures in
// 1.45 ms on one core of the 2-core EPYC VM.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/image.h"
#include "platform/environment_response.h"

namespace penumbra::platform {

// Debevec & Malik's hat weight, as lighting::hatWeight: 0 at the clipped codes 0 and 255.
inline constexpr float hatWeight(int z) {
  return float(z <= 127 ? z : 255 - z);
}

class BracketMerge {
 public:
  // `response`: the exposure each code records, per channel (curveResponse or
  // calibratedResponse); `exposuresMs`: the bracket's times, increasing. Throws
  // std::invalid_argument for an empty bracket, a time that is not positive and finite or
  // not longer than the one before, or a bad exposure scale.
  BracketMerge(const ChannelResponse& response, std::span<const double> exposuresMs,
               double exposureScale);

  size_t exposures() const { return radiance_.size(); }
  // R_j: the radiance table of exposure j alone (the single-frame linearisation of it).
  const ChannelTables& radiance(size_t j) const { return radiance_[j]; }

  // Merges one 8-bit BGR frame per exposure (frames[j] of exposure j, rows strides[j] bytes
  // apart) into `out` (RGB, resized to width × height). Returns the number of pixels with a
  // channel saturated in every exposure. Throws std::invalid_argument when the counts differ
  // from exposures().
  size_t merge(std::span<const uint8_t* const> frames, std::span<const size_t> strides,
               uint32_t width, uint32_t height, core::ImageF& out) const;

 private:
  std::vector<ChannelTables> radiance_;          // R_j
  std::vector<ChannelTables> weightedRadiance_;  // w(z) · R_j(z), rounded once
  std::array<float, 256> weight_{};              // w(z)
};

}  // namespace penumbra::platform
