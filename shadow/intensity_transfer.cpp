#include "shadow/intensity_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.h"

namespace penumbra::shadow {

TransferKind transferKindFor(raster::Accumulation accumulation) {
  switch (accumulation) {
    case raster::Accumulation::kFixed8_8:
      return TransferKind::kFineLevels;
    case raster::Accumulation::kLinear:
      return TransferKind::kLightShares;
    case raster::Accumulation::kU8:
      break;
  }
  return TransferKind::kWholeLevels;
}

void lightShares(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                 std::span<core::Rgb16> out) {
  if (transfers.size() != out.size()) {
    throw std::invalid_argument("lightShares: transfers and out differ in length");
  }
  for (size_t j = 0; j < transfers.size(); ++j) {
    out[j] = {lightShare(transfers[j].x, totalRadiance.x),
              lightShare(transfers[j].y, totalRadiance.y),
              lightShare(transfers[j].z, totalRadiance.z)};
  }
}

int sourceSet(uint64_t seed, uint64_t sourceId) {
  // State of a SplitMix64 stream seeded with `seed` after `sourceId` steps: each id draws
  // an independent, reproducible value.
  const uint64_t id = core::splitmix64(seed + sourceId * 0x9E3779B97F4A7C15ull);
  return (id & 1) == 0 ? 1 : 2;
}

namespace {

// T in the precision of the output: codes, whose differences are whole-level S (Rgb8), or
// continuous levels, whose differences are S in 8.8 levels (Rgb16; ToneCurve::levels).
template <class Out>
struct Tone;

template <>
struct Tone<core::Rgb8> {
  using Value = core::Rgb8;
  static Value at(const ToneCurve& tone, const glm::dvec3& radiance) { return tone.map(radiance); }
  // T is monotone and low <= high, so each difference is in [0, 255].
  static core::Rgb8 drop(const Value& high, const Value& low) {
    return {static_cast<uint8_t>(high.r - low.r), static_cast<uint8_t>(high.g - low.g),
            static_cast<uint8_t>(high.b - low.b)};
  }
};

template <>
struct Tone<core::Rgb16> {
  using Value = glm::dvec3;
  static Value at(const ToneCurve& tone, const glm::dvec3& radiance) {
    return tone.levels(radiance);
  }
  // round(256 (high - low)), ties up, clamped to [0, 255 * 256] (levels() is monotone up to
  // the rounding of its slopes, ~1e-16 of a level).
  static uint16_t fine(double high, double low) {
    const double scaled = std::floor((high - low) * 256.0 + 0.5);
    return static_cast<uint16_t>(std::clamp(scaled, 0.0, double(core::kMaxFineLevel)));
  }
  static core::Rgb16 drop(const Value& high, const Value& low) {
    return {fine(high.x, low.x), fine(high.y, low.y), fine(high.z, low.z)};
  }
};

template <class Out>
void fig4Transfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                   std::span<const uint8_t> sets, const ToneCurve& tone, std::span<Out> out) {
  if (transfers.size() != sets.size() || transfers.size() != out.size()) {
    throw std::invalid_argument("intensityTransfers: transfers, sets and out differ in length");
  }
  // Gibson 2003 Fig. 4: V1 = V2 = L_i, C1 = C2 = T(L_i); each source subtracts its
  // transfer from its own set's running radiance and takes the drop in T as S_ij.
  std::array<glm::dvec3, 2> v = {totalRadiance, totalRadiance};
  const typename Tone<Out>::Value c0 = Tone<Out>::at(tone, totalRadiance);
  std::array<typename Tone<Out>::Value, 2> c = {c0, c0};
  for (size_t j = 0; j < transfers.size(); ++j) {
    if (sets[j] != 1 && sets[j] != 2) {
      throw std::invalid_argument("intensityTransfers: set must be 1 or 2");
    }
    const int k = sets[j] - 1;
    const glm::dvec3 l = glm::max(transfers[j], glm::dvec3(0.0));
    if (l == glm::dvec3(0.0)) {  // v - 0 is v: T does not move (the product's far side)
      out[j] = Out{};
      continue;
    }
    v[k] -= l;
    const typename Tone<Out>::Value next = Tone<Out>::at(tone, v[k]);
    out[j] = Tone<Out>::drop(c[k], next);  // V only decreases
    c[k] = next;
  }
}

// S_j = T(L_i - B_j) - T(L_i - B_j - L_ij), B_j = sum_{k<j} q_k L_ik, with q_k = shareOf(k).
template <class Out, class ShareOf>
void gradedTransfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                     ShareOf shareOf, const ToneCurve& tone, std::span<Out> out) {
  glm::dvec3 before(0.0);  // B_j, summed in source order
  // T(L_i - B_j) is mapped again only when B_j moved: a cluster not occluded there (q = 0)
  // or without light there leaves it, and the same bits give the same code.
  glm::dvec3 mappedAt(std::numeric_limits<double>::quiet_NaN());
  typename Tone<Out>::Value high{};
  for (size_t j = 0; j < transfers.size(); ++j) {
    const glm::dvec3 l = glm::max(transfers[j], glm::dvec3(0.0));
    if (l == glm::dvec3(0.0)) {  // S = T(x) - T(x - 0) = 0; B_j + q * 0 = B_j (B_j >= +0)
      out[j] = Out{};
      continue;
    }
    const glm::dvec3 at = totalRadiance - before;
    if (at != mappedAt) {  // NaN never compares equal: the first vertex always maps
      high = Tone<Out>::at(tone, at);
      mappedAt = at;
    }
    out[j] = Tone<Out>::drop(high, Tone<Out>::at(tone, at - l));  // at - l <= at
    before += shareOf(j) * l;
  }
}

template <class Out>
void checkedGradedOne(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                      double q, const ToneCurve& tone, std::span<Out> out) {
  if (transfers.size() != out.size()) {
    throw std::invalid_argument(
        "intensityTransfersForOcclusion: transfers and out differ in length");
  }
  if (!(q >= 0.0 && q <= 1.0)) {
    throw std::invalid_argument("intensityTransfersForOcclusion: q must be in [0, 1]");
  }
  gradedTransfers(
      totalRadiance, transfers, [q](size_t) { return q; }, tone, out);
}

template <class Out>
void checkedGradedEach(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                       std::span<const double> q, const ToneCurve& tone, std::span<Out> out) {
  if (transfers.size() != out.size() || q.size() != out.size()) {
    throw std::invalid_argument(
        "intensityTransfersForOcclusions: transfers, q and out differ in length");
  }
  for (double share : q) {
    if (!(share >= 0.0 && share <= 1.0)) {
      throw std::invalid_argument("intensityTransfersForOcclusions: every q must be in [0, 1]");
    }
  }
  gradedTransfers(
      totalRadiance, transfers, [q](size_t j) { return q[j]; }, tone, out);
}

}  // namespace

#define PENUMBRA_INTENSITY_TRANSFERS(Out)                                                         \
  void intensityTransfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers, \
                          std::span<const uint8_t> sets, const ToneCurve& tone,                   \
                          std::span<Out> out) {                                                   \
    fig4Transfers(totalRadiance, transfers, sets, tone, out);                                     \
  }                                                                                               \
  void intensityTransfersForOcclusion(const glm::dvec3& totalRadiance,                            \
                                      std::span<const glm::dvec3> transfers, double q,            \
                                      const ToneCurve& tone, std::span<Out> out) {                \
    checkedGradedOne(totalRadiance, transfers, q, tone, out);                                     \
  }                                                                                               \
  void intensityTransfersForOcclusions(                                                           \
      const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,                     \
      std::span<const double> q, const ToneCurve& tone, std::span<Out> out) {                     \
    checkedGradedEach(totalRadiance, transfers, q, tone, out);                                    \
  }
PENUMBRA_INTENSITY_TRANSFERS(core::Rgb8)
PENUMBRA_INTENSITY_TRANSFERS(core::Rgb16)
#undef PENUMBRA_INTENSITY_TRANSFERS

}  // namespace penumbra::shadow
