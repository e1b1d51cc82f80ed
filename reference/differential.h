// Differential rendering (Debevec 1998; Gibson 2003 §7 eq. 1): the reference's final
// frame from the background photograph and the light the product takes away,
//
//   I_final = T(L_b - (L_noobj - L_obj)),   L_b = T^-1(background pixel),
//
// and, where the camera sees the product, T(its radiance) (mixed by coverage at its
// silhouette). T is the bundle's camera response (shadow::ToneCurve).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "reference/reference_renderer.h"
#include "shadow/intensity_transfer.h"

namespace penumbra::reference {

// T^-1 for one channel: a radiance that T maps back to `code`. T steps up to code k at
// threshold(k), so code k stands for the radiance interval [threshold(k),
// threshold(k + 1)); the inverse is the interval's midpoint (the unbiased guess for a
// radiance known only to lie in it). Ends: code 0 covers [0, threshold(1)) (radiance is
// not negative), code 255 is open above and maps to threshold(255) itself. A code T never
// produces (an empty interval, or a threshold at +inf) has no preimage; it maps to the
// radiance of the nearest lower code that T does produce, so T(inverseTone(k)) == k holds
// exactly for every code T can output (tests check all 256).
double inverseTone(const shadow::ToneCurve& tone, uint8_t code);

// The 256 inverses, indexed by code.
std::vector<double> inverseToneTable(const shadow::ToneCurve& tone);

// The radiances [lo, hi] that T maps to `code` (the interval inverseTone takes the midpoint
// of): lo = threshold(code) (0 for code 0: radiance is not negative), hi the largest double
// below threshold(code + 1) (the largest finite one for 255). A code T never produces gets
// the point [inverseTone, inverseTone].
struct ToneInterval {
  double lo = 0, hi = 0;
};
ToneInterval toneInterval(const shadow::ToneCurve& tone, uint8_t code);

struct DifferentialFrame {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // I_final, RGBA8 (alpha 255)
  // What the photograph's 8 bits leave open. L_b is known only to lie in its code's
  // interval [lo, hi], so I_final lies between T(lo - (L_noobj - L_obj)) and T(hi - ...),
  // per channel (T is monotone; the product's coverage mix is too). Near black the gamma
  // curve makes that span wide: a floor photographed at code 103 under gamma 2.2 is
  // uncertain by +-1.07 % of its radiance, and a shadow that takes 99.5 % of it away lands
  // anywhere between 0 and 16 (9 at the midpoint) (docs/reference.md). RGBA8 like rgba; lower <=
  // rgba <= upper in every sample.
  std::vector<uint8_t> lower, upper;
  std::vector<glm::vec3> radiance;            // the HDR value T is applied to
  std::vector<uint8_t> shadowMask;            // 255 where L_noobj - L_obj changes a byte
  size_t shadowPixels = 0, objectPixels = 0;  // mask count; pixels with any product sample
};

// Per pixel with product coverage c: HDR = (1 - c) (L_b - roomDelta) + c objectRadiance,
// per channel, then T; lower and upper the same with L_b at its interval's ends. The shadow mask
// marks pixels without product samples whose bytes differ from the background, i.e. where the
// product's shadow is visible in 8 bits. `background` is RGBA8 of the image's size; throws
// std::invalid_argument otherwise.
DifferentialFrame composeDifferential(const ReferenceImage& image,
                                      std::span<const uint8_t> background,
                                      const shadow::ToneCurve& tone);

// Pixels whose RGB bytes differ from the background photograph (RGBA8, the frame's size):
// 0 when the product is out of sight and casts no shadow, since differential rendering
// leaves the photograph as it is there.
size_t changedPixels(const DifferentialFrame& frame, std::span<const uint8_t> background);

// One render's Monte Carlo noise in 8-bit levels, from two renders of the same scene with
// unrelated seeds: they differ only by their noise, so the RMS of their difference over
// the RGB samples of either one's shadow region, divided by sqrt(2), estimates one render's
// noise. 0 when neither has a shadow pixel; `samples` (when given) gets the count averaged.
double shadowNoiseRms(const DifferentialFrame& a, const DifferentialFrame& b,
                      size_t* samples = nullptr);

// The shadow mask as an RGBA8 image (white where the shadow changes a byte, opaque).
std::vector<uint8_t> shadowMaskRgba(const DifferentialFrame& frame);

}  // namespace penumbra::reference
