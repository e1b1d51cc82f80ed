// Tone mapping of HDR frames for display: the global photographic operator of Reinhard, Stark,
// Shirley & Ferwerda 2002 ("Photographic tone reproduction for digital images", SIGGRAPH),
// extended to video as Havran et al. 2005 §5.1 do: its two parameters, the world luminance
// (the log-average L̄w) and the key a, are smoothed over time so that a bright object entering
// the view does not make the whole picture jump (brightness flicker).
//
// Per frame, with Lw the Rec. 709 luminance of a pixel (core/colour.h):
//   L̄w = exp(mean(ln(δ + Lw)))                                      (Reinhard 2002, eq. 1)
//   L = (a / L̄w) Lw                                                  (eq. 2)
//   Ld = L (1 + L / Lwhite²) / (1 + L)                                (eq. 4)
//   RGBd = RGBw · Ld / Lw, then the sRGB transfer function to 8 bits (IEC 61966-2-1).
// The key a is fixed, or estimated per frame as in Reinhard 2002b ("Parameter estimation for
// photographic tone reproduction", JGT 7(1)): a = 0.18 · 4^((2 log2 L̄w − log2 Lmin − log2 Lmax)
// / (log2 Lmax − log2 Lmin)). Lwhite is the frame's largest luminance after scaling, its log
// smoothed like the other two (an addition: an unsmoothed Lwhite flickers with the brightest
// pixel). Smoothing is exponential in the log domain: p ← p + s (p_frame − p), s in (0, 1]; the
// first frame sets p.
//
// This is not OpenCV's TonemapReinhard (Reinhard & Devlin 2005, per-frame min/max
// normalisation, state kept between calls: design §6). Arithmetic: portable_log_exp.h and a
// fixed pixel order, so the bytes are the same everywhere.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace penumbra::envmap {

class ToneMapError : public core::Error {
 public:
  using core::Error::Error;
};

struct ReinhardOptions {
  double key = 0.18;       // a; 0: estimated per frame (Reinhard 2002b)
  double smoothing = 0.1;  // s: weight of the new frame's parameters; 1 = no smoothing
  double delta = 1e-4;     // δ of eq. 1, in the image's radiance units
};

class ReinhardToneMapper {
 public:
  // Throws ToneMapError for a key < 0, a smoothing outside (0, 1] or a delta ≤ 0.
  explicit ReinhardToneMapper(const ReinhardOptions& options = {});

  // Maps one frame to 8-bit sRGB and advances the smoothed parameters. Throws ToneMapError
  // naming `label` for an empty image, a wrong pixel count or a negative or non-finite value.
  core::Image8 map(const core::ImageF& hdr, const std::string& label = "HDR frame");

  // The smoothed parameters used by the last map(): L̄w, a and Lwhite (scaled).
  double worldLuminance() const;
  double key() const;
  double white() const;

 private:
  ReinhardOptions options_;
  bool started_ = false;
  double logWorld_ = 0, logKey_ = 0, logWhite_ = 0;
  std::vector<uint8_t> srgb_;  // the sRGB transfer function, kSrgbSteps + 1 entries
};

}  // namespace penumbra::envmap
