#include "envmap/light_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::envmap {

FirTaps normalisedHavranFir() {
  double sum = 0;
  for (double w : kHavranFirPrinted) sum += w;
  FirTaps taps{};
  for (size_t k = 0; k < kFirTaps; ++k) taps[k] = kHavranFirPrinted[k] / sum;
  return taps;
}

TemporalLightFilter::TemporalLightFilter(const FirTaps& taps) : taps_(taps) {}

// y[t] = Σ_k w_k x[t − k], k = 0 … 8 in that order; slot (t − k) mod 9 of the ring holds x[t − k].
glm::dvec3 TemporalLightFilter::fir(const std::array<glm::dvec3, kFirTaps>& ring) const {
  glm::dvec3 sum(0.0);
  for (size_t k = 0; k < kFirTaps; ++k) sum += taps_[k] * ring[(frame_ + kFirTaps - k) % kFirTaps];
  return sum;
}

LightSet TemporalLightFilter::push(const LightSet& lights) {
  // Ids index a table: bound them so that a corrupt id cannot allocate without limit.
  constexpr uint32_t kMaxId = 1u << 20;
  const size_t slot = frame_ % kFirTaps;
  const glm::dvec3 total = totalPower(lights);
  if (frame_ == 0) totals_.fill(total);
  totals_[slot] = total;
  filteredTotal_ = glm::max(fir(totals_), glm::dvec3(0.0));  // negative taps can undershoot

  LightSet out(lights);
  glm::dvec3 shareSum(0.0);
  for (DirectionalLight& light : out) {
    if (light.id == 0 || light.id > kMaxId)
      throw std::invalid_argument("TemporalLightFilter: light id " + std::to_string(light.id) +
                                  " outside 1.." + std::to_string(kMaxId));
    if (tracks_.size() < light.id) tracks_.resize(light.id);
    Track& track = tracks_[light.id - 1];
    // This frame's share of the total, per channel (equal shares where a channel is dark).
    glm::dvec3 share(0.0);
    for (int c = 0; c < 3; ++c)
      share[c] = total[c] > 0 ? light.power[c] / total[c] : 1.0 / double(out.size());
    if (track.lastFrame == 0 || track.lastFrame != frame_) {  // new, or back after a gap
      track.directions.fill(light.direction);
      track.shares.fill(share);
    }
    track.directions[slot] = light.direction;
    track.shares[slot] = share;
    track.lastFrame = frame_ + 1;
    const glm::dvec3 d = fir(track.directions);
    const double length = std::sqrt(glm::dot(d, d));
    // Havran 2005 §3.3: filtered in 3D, then normalised to a unit vector. (The sum can only
    // vanish for directions spread over more than a hemisphere; keep the raw one then.)
    if (length > 1e-9) light.direction = d / length;
    // Beyond §3.3, which filters the total and the directions: each light's share of the
    // total, filtered too. A light's colour is the colour of the map pixel its sample hit,
    // so sensor noise reshuffles the shares (and the shadows' colours) every frame however
    // calm the total is. Held here, normalised below so the powers add up to the total.
    light.power = glm::max(fir(track.shares), glm::dvec3(0.0));
    shareSum += light.power;
  }
  for (DirectionalLight& light : out) {
    for (int c = 0; c < 3; ++c)
      light.power[c] = shareSum[c] > 0 ? filteredTotal_[c] * (light.power[c] / shareSum[c])
                                       : filteredTotal_[c] / double(out.size());
  }
  ++frame_;
  return out;
}

}  // namespace penumbra::envmap
