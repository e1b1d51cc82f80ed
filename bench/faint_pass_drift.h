// 8-bit drift of many faint shadow passes (Gibson 2003 §10: "rounding errors accumulate"
// when many passes each subtract a small 8-bit intensity transfer; design §5).
//
// Model, per receiver vertex: radiance L (grey), N sources whose transfers L_j carry together
// the share `shadowShare` of L (weights pseudo-random in [0.5, 1.5), seeded), every pass
// masked by the same 8-bit mask M (255 = fully occluded, 128 = half-lit penumbra). The frame
// buffer starts at T(L) and each pass does dst = max(dst − round(S_j·M/255), 0) exactly as the
// rasterizer (simd::subtractMaskedU8, spec §7). The HDR answer is T(L − Σ (M/255)·L_j).
// Drift = |8-bit result − HDR answer| in 8-bit levels.
//
// Policies for S_j (shadow/intensity_transfer.h):
//  - independent: each S_j = T(L) − T(L − L_j), rounded alone (q = 0 of the graded form);
//  - fig4: Gibson 2003 Fig. 4, two pseudo-random sets, telescoping within each set;
//  - graded: intensityTransfersForOcclusion with q = M/255, the occluded share the frame
//    measures (what Penumbra uses once a frame has observed the occlusion, docs/fig3.md);
//  - graded-fixed8_8: the same S_j, but each pass adds S_j·M/255 rounded to 1/256 level and
//    the frame rounds the sum once: the renderer's fixed-point accumulation
//    (raster::Accumulation::kFixed8_8, spec §8), which the shadow pipeline uses.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/random.h"
#include "shadow/intensity_transfer.h"
#include "simd/u8_ops.h"

namespace penumbra::bench {

enum class DriftPolicy { kIndependent, kFig4, kGraded, kGradedFixed8_8 };

inline const char* driftPolicyName(DriftPolicy p) {
  switch (p) {
    case DriftPolicy::kIndependent:
      return "independent";
    case DriftPolicy::kFig4:
      return "fig4";
    case DriftPolicy::kGraded:
      return "graded";
    case DriftPolicy::kGradedFixed8_8:
      return "graded-fixed8_8";
  }
  return "?";
}

struct DriftResult {
  double meanAbs = 0;  // over the vertices
  int maxAbs = 0;
  double meanSigned = 0;  // 8-bit result − HDR answer: > 0 means too little shadow
};

// `vertices` radiance levels spread over (0, 1] of the tone curve's range.
inline DriftResult measureFaintPassDrift(const shadow::ToneCurve& tone, int passes, uint8_t mask,
                                         DriftPolicy policy, double shadowShare = 0.5,
                                         int vertices = 64, uint64_t seed = 1) {
  DriftResult r;
  std::vector<glm::dvec3> transfers(static_cast<size_t>(passes));
  std::vector<uint8_t> sets(static_cast<size_t>(passes));
  std::vector<core::Rgb8> s(static_cast<size_t>(passes));
  std::vector<core::Rgb16> fine(static_cast<size_t>(passes));
  long sumAbs = 0, sumSigned = 0;
  for (int v = 0; v < vertices; ++v) {
    const double radiance = double(v + 1) / double(vertices);
    double weightSum = 0;
    std::vector<double> w(static_cast<size_t>(passes));
    for (int j = 0; j < passes; ++j) {
      const uint64_t h = core::splitmix64(seed * 1000003u + uint64_t(v) * 7919u + uint64_t(j));
      w[size_t(j)] = 0.5 + double(h >> 11) * 0x1.0p-53;
      weightSum += w[size_t(j)];
    }
    double blocked = 0;
    for (int j = 0; j < passes; ++j) {
      const double l = shadowShare * radiance * w[size_t(j)] / weightSum;
      transfers[size_t(j)] = glm::dvec3(l);
      sets[size_t(j)] = uint8_t(shadow::sourceSet(seed, uint64_t(j)));
      blocked += double(mask) / 255.0 * l;
    }
    const glm::dvec3 total(radiance);
    switch (policy) {
      case DriftPolicy::kIndependent:
        shadow::intensityTransfersForOcclusion(total, transfers, 0.0, tone, s);
        break;
      case DriftPolicy::kFig4:
        shadow::intensityTransfers(total, transfers, sets, tone, s);
        break;
      case DriftPolicy::kGraded:
      case DriftPolicy::kGradedFixed8_8:
        shadow::intensityTransfersForOcclusion(total, transfers, double(mask) / 255.0, tone, s);
        break;
    }
    uint8_t dst = tone(radiance);
    if (policy == DriftPolicy::kGradedFixed8_8) {
      // 8.8 S and the mask as an occluded weight (spec §7-8), summed in 1/256 levels,
      // saturating at 65535 as the u16 planes do.
      shadow::intensityTransfersForOcclusion(total, transfers, double(mask) / 255.0, tone, fine);
      const uint32_t occluded = (uint32_t{mask} * 65536u + 127u) / 255u;
      uint32_t sum = 0;
      for (int j = 0; j < passes; ++j) {
        sum = std::min(sum + simd::fineAmount(fine[size_t(j)].r, occluded), 65535u);
      }
      const uint32_t drop = simd::fixed8_8Levels(sum);
      dst = drop >= dst ? uint8_t{0} : uint8_t(dst - drop);
    } else {
      for (int j = 0; j < passes; ++j) dst = simd::subtractMaskedU8(dst, s[size_t(j)].r, mask);
    }
    const int exact = tone(radiance - blocked);
    const int diff = int(dst) - exact;
    sumAbs += std::abs(diff);
    sumSigned += diff;
    r.maxAbs = std::max(r.maxAbs, std::abs(diff));
  }
  r.meanAbs = double(sumAbs) / double(vertices);
  r.meanSigned = double(sumSigned) / double(vertices);
  return r;
}

}  // namespace penumbra::bench
