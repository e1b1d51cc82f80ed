// Temporal filtering of live lights (Havran et al. 2005 §3.3): a 9-tap FIR low-pass on the
// environment's total power and on every light's direction (filtered as a 3D vector, then
// renormalised), lights tracked from frame to frame by their Halton index (their id).
//
// The printed coefficients sum to 1.09245, not 1; the paper asks that "the overall energy in
// the system is preserved, which is naturally achieved through normalizing the filter
// weighting coefficients", so they are divided by their sum (docs/live-lighting.md gives both
// sets and the frequency response). The filter is causal: its output is centred 4 frames back.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "envmap/directional_light.h"

namespace penumbra::envmap {

inline constexpr size_t kFirTaps = 9;
using FirTaps = std::array<double, kFirTaps>;

// Havran 2005 §3.3 as printed: an equiripple design for 21 Hz sampling, pass 7 Hz, stop 9 Hz.
inline constexpr FirTaps kHavranFirPrinted = {0.06216, 0.01296,  -0.13816, 0.28315, 0.65223,
                                              0.28315, -0.13816, 0.01296,  0.06216};
// The printed taps divided by their sum (added left to right): a DC gain of 1.
FirTaps normalisedHavranFir();

class TemporalLightFilter {
 public:
  explicit TemporalLightFilter(const FirTaps& taps = normalisedHavranFir());

  // Pushes one frame's lights (ids ≥ 1, e.g. from EnvmapDistribution::sample) and returns them
  // filtered: the same ids in the same order, each direction the renormalised FIR of that id's
  // last 9 directions, and powers that add up to the FIR of the frames' total powers, shared
  // among the lights per channel by the FIR of each light's share of its frame's total
  // (clamped at 0, renormalised to sum to 1). A light seen for the first time (or again after
  // missing a frame) starts with a history of its current direction and share, and the first
  // frame fills the power history, so a constant input passes unchanged.
  LightSet push(const LightSet& lights);

  // The filtered total power of the last frame pushed.
  const glm::dvec3& filteredTotalPower() const { return filteredTotal_; }
  uint64_t framesPushed() const { return frame_; }

 private:
  struct Track {
    std::array<glm::dvec3, kFirTaps> directions{};
    std::array<glm::dvec3, kFirTaps> shares{};  // of the frame's total, per channel
    uint64_t lastFrame = 0;  // frame number + 1 of the last push that held the light; 0: never
  };
  glm::dvec3 fir(const std::array<glm::dvec3, kFirTaps>& ring) const;

  FirTaps taps_;
  std::vector<Track> tracks_;  // by id − 1
  std::array<glm::dvec3, kFirTaps> totals_{};
  glm::dvec3 filteredTotal_{0.0};
  uint64_t frame_ = 0;
};

}  // namespace penumbra::envmap
