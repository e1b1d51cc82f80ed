#include "shadow/intensity_transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random.h"

namespace penumbra::shadow {

int sourceSet(uint64_t seed, uint64_t sourceId) {
  // State of a SplitMix64 stream seeded with `seed` after `sourceId` steps: each id draws
  // an independent, reproducible value.
  const uint64_t id = core::splitmix64(seed + sourceId * 0x9E3779B97F4A7C15ull);
  return (id & 1) == 0 ? 1 : 2;
}

void intensityTransfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                        std::span<const uint8_t> sets, const ToneCurve& tone,
                        std::span<core::Rgb8> out) {
  if (transfers.size() != sets.size() || transfers.size() != out.size()) {
    throw std::invalid_argument("intensityTransfers: transfers, sets and out differ in length");
  }
  // Gibson 2003 Fig. 4: V1 = V2 = L_i, C1 = C2 = T(L_i); each source subtracts its
  // transfer from its own set's running radiance and takes the drop in T as S_ij.
  std::array<glm::dvec3, 2> v = {totalRadiance, totalRadiance};
  const core::Rgb8 c0 = tone.map(totalRadiance);
  std::array<core::Rgb8, 2> c = {c0, c0};
  for (size_t j = 0; j < transfers.size(); ++j) {
    if (sets[j] != 1 && sets[j] != 2) {
      throw std::invalid_argument("intensityTransfers: set must be 1 or 2");
    }
    const int k = sets[j] - 1;
    const glm::dvec3 l = glm::max(transfers[j], glm::dvec3(0.0));
    if (l == glm::dvec3(0.0)) {  // v - 0 is v: T does not move (the product's far side)
      out[j] = core::Rgb8{0, 0, 0};
      continue;
    }
    v[k] -= l;
    const core::Rgb8 next = tone.map(v[k]);
    // T is monotone and V only decreases, so each difference is in [0, 255].
    out[j] =
        core::Rgb8{static_cast<uint8_t>(c[k].r - next.r), static_cast<uint8_t>(c[k].g - next.g),
                   static_cast<uint8_t>(c[k].b - next.b)};
    c[k] = next;
  }
}

namespace {

// S_j = T(L_i - B_j) - T(L_i - B_j - L_ij), B_j = sum_{k<j} q_k L_ik, with q_k = shareOf(k).
template <class ShareOf>
void gradedTransfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                     ShareOf shareOf, const ToneCurve& tone, std::span<core::Rgb8> out) {
  glm::dvec3 before(0.0);  // B_j, summed in source order
  // T(L_i - B_j) is mapped again only when B_j moved: a cluster not occluded there (q = 0)
  // or without light there leaves it, and the same bits give the same code.
  glm::dvec3 mappedAt(std::numeric_limits<double>::quiet_NaN());
  core::Rgb8 high{};
  for (size_t j = 0; j < transfers.size(); ++j) {
    const glm::dvec3 l = glm::max(transfers[j], glm::dvec3(0.0));
    if (l == glm::dvec3(0.0)) {  // S = T(x) - T(x - 0) = 0; B_j + q * 0 = B_j (B_j >= +0)
      out[j] = core::Rgb8{0, 0, 0};
      continue;
    }
    const glm::dvec3 at = totalRadiance - before;
    if (at != mappedAt) {  // NaN never compares equal: the first vertex always maps
      high = tone.map(at);
      mappedAt = at;
    }
    const core::Rgb8 low = tone.map(at - l);
    // T is monotone and at - l <= at, so each difference is in [0, 255].
    out[j] = core::Rgb8{static_cast<uint8_t>(high.r - low.r), static_cast<uint8_t>(high.g - low.g),
                        static_cast<uint8_t>(high.b - low.b)};
    before += shareOf(j) * l;
  }
}

}  // namespace

void intensityTransfersForOcclusion(const glm::dvec3& totalRadiance,
                                    std::span<const glm::dvec3> transfers, double q,
                                    const ToneCurve& tone, std::span<core::Rgb8> out) {
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

void intensityTransfersForOcclusions(const glm::dvec3& totalRadiance,
                                     std::span<const glm::dvec3> transfers,
                                     std::span<const double> q, const ToneCurve& tone,
                                     std::span<core::Rgb8> out) {
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

}  // namespace penumbra::shadow
