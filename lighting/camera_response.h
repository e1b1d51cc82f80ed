// The camera response T() from bracketed exposures: our own Debevec & Malik 1997 solve
// (Gibson & Chalmers 2003 §4: "the camera response function is recovered from a set of
// differently exposed images" and used to build T() and its inverse). Not OpenCV's
// CalibrateDebevec, whose result varies with its sample count and random sampling; here the
// samples are chosen by a seeded counter-based hash stratified over code values, and the
// least-squares system is solved by a Cholesky factorisation of the normal equations in a
// fixed order, so the same bracket always gives the same curve, bit for bit.
//
// For each channel, g(z) = ln(E * dt) for code z, up to one constant fixed by g(128) = 0
// (radiance is relative). The constant is fixed per channel, so the merged channels carry
// independent scales: white balance is a separate step (e.g. from a grey card), as in
// Debevec & Malik §2.1. Minimised (Debevec & Malik eq. 3, hat weight w(z) = min(z, 255 - z)):
//   sum_ij [w(Z_ij) (g(Z_ij) - ln E_i - ln dt_j)]^2 + lambda sum_z [w(z) g''(z)]^2
// Offline only (libm log/exp); the per-frame path uses the tables (toneSamples) instead.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lighting/hdr_image.h"

namespace penumbra::lighting {

// Hat weight of Debevec & Malik: 0 at codes 0 and 255 (clipped), peak in the middle.
inline double hatWeight(int z) {
  return double(z <= 127 ? z : 255 - z);
}

// One point of a response table: the radiance (relative, exposure time 1) that the camera
// records as the continuous code `value`. shadow::ToneCurve::fromSamples takes exactly this
// ({radiance, value}); lighting/ does not depend on shadow/, so the lead converts.
struct ToneSample {
  double radiance = 0;
  double value = 0;
};

struct ResponseOptions {
  int samplesPerChannel = 400;  // pixels per channel, 2..2000 (Debevec: N(P-1) > 255)
  double smoothness = 10;       // lambda (OpenCV's default; 50 over-smooths the dark codes)
  uint64_t seed = 1;            // sample selection
  // A non-monotone recovered g is flattened to its running maximum (with a warning); if
  // more than this fraction of the 256 codes needed it, the bracket is rejected.
  double maxRepairedFraction = 0.1;
};

struct CameraResponse {
  // g per channel (R, G, B): ln(radiance * exposure time) recorded as code z.
  std::array<std::array<double, 256>, 3> logExposure{};
  std::array<int, 3> repairedCodes{0, 0, 0};  // codes changed by the monotone repair
  std::vector<std::string> warnings;          // what was repaired, and how

  // T() of one channel as 256 samples {exp(g(z)), z}, z = 0..255, radiance non-decreasing.
  std::vector<ToneSample> toneSamples(int channel) const;
  // One curve for all channels: g averaged over R, G, B (a geometric mean of the three
  // radiances per code). Use it where the bundle stores a single T().
  std::vector<ToneSample> greyToneSamples() const;
  // T^-1 for one channel: the radiance at exposure time 1 recorded as code z.
  double radiance(int channel, int z) const;
};

// Validates a bracket: >= 2 exposures, equal non-zero sizes, rgb of 3 * width * height
// bytes, finite positive and pairwise distinct exposure times. Throws HdrError naming the
// exposure.
void checkBracket(std::span<const Exposure> bracket);

// Recovers the response. Throws HdrError on an invalid bracket, when a channel has too few
// usable samples (pixels clipped in every exposure carry no information), or when the
// recovered curve is too far from monotone (see ResponseOptions::maxRepairedFraction).
CameraResponse recoverResponse(std::span<const Exposure> bracket,
                               const ResponseOptions& options = {});

}  // namespace penumbra::lighting
