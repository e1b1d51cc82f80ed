// LDR intensity transfers S_ij from HDR radiance transfers L_ij (Gibson 2003 §7.1–7.1.1,
// Fig. 4), and the camera response T() they are measured through.
//
// The frame buffer holds 8-bit colours I = T(L). Subtracting S_ij * M_ij from it must
// mimic T(L_i - sum_j L_ij M_ij) (§7.1, Eq. 3–4). Because the masks M are unknown before
// rendering, Fig. 4 assumes the sources fall into two equally likely sets, each occluded
// as a whole, and makes each set's transfers telescope: within a set,
// sum_j S_ij = T(L_i) - T(L_i - sum_j L_ij).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "core/colour.h"
#include "raster/frame_trace.h"
#include "shadow/tone_curve.h"

namespace penumbra::shadow {

// Which of the two occlusion sets of Gibson 2003 §7.1.1 source patch `sourceId` belongs
// to: 1 for an even pseudo-random id, 2 for an odd one. A counter-based hash of
// (seed, id) rather than a running generator, so a source keeps its set from frame to
// frame whatever else is in the source list (the paper's "randomly generated id").
int sourceSet(uint64_t seed, uint64_t sourceId);

// What a blending pass carries per vertex, by accumulation mode (docs/pipeline-spec.md §8).
enum class TransferKind : uint8_t {
  kWholeLevels,  // S in whole levels, as 8.8 (u8 accumulation)
  kFineLevels,   // S in 8.8 levels (fixed8_8)
  kLightShares,  // the share of the vertex's light, in units of 1/65280 (linear)
};

// The kind of transfer `accumulation` sums.
TransferKind transferKindFor(raster::Accumulation accumulation);

// Linear accumulation's transfers: per channel, the share of the vertex's light L_i that
// each source (cluster) j carries, L_ij / L_i clamped to [0, 1], in units of 1/65280 (so
// that a share of 1 is the 8.8 value of 255 levels and the raster's 8.8 interpolation and
// products apply unchanged), rounded half up. 0 where L_i <= 0. Unlike S, the shares do not
// depend on T or on which other sources are occluded: summed over the occluded sources
// they are the occluded share of the light at any pixel, exactly as the shade table needs.
void lightShares(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                 std::span<core::Rgb16> out);

// One channel of lightShares: `part` of `whole` in units of 1/65280, rounded half up.
// min(part / whole, 1) * 65280 + 0.5 lies in [0.5, 65280.5]; its floor fits uint16_t.
// 0 for a NaN quotient (infinite part and whole; bundles hold none), rather than converting
// NaN, which C++ leaves undefined (x86 gave 0 too).
inline uint16_t lightShare(double part, double whole) {
  if (!(whole > 0.0) || !(part > 0.0)) return 0;
  const double q = part / whole;
  if (q != q) return 0;
  return static_cast<uint16_t>(std::floor((1.0 < q ? 1.0 : q) * core::kMaxFineLevel + 0.5));
}

// Each function below writes S in one of two precisions, chosen by the element of `out`:
// core::Rgb8, whole levels, the differences of T's codes (the paper's 8-bit S, which u8
// accumulation rounds each pixel to anyway); core::Rgb16, 8.8 levels, the differences of
// ToneCurve::levels() rounded to 1/256 level, so that a shadow spread over many faint passes
// is not quantized a whole level per pass (fixed8_8 accumulation, docs/pipeline-spec.md §8).

// Fig. 4 for one receiver vertex. `totalRadiance` is L_i (per channel); `transfers` are
// the L_ij of the contributing sources in the frame's source order (decreasing average
// transfer, §7.1.1 pre-process); `sets[j]` is 1 or 2 (sourceSet). Writes S_ij to `out`
// (same length as `transfers`). Negative transfers count as 0. Throws
// std::invalid_argument on length mismatch or a set other than 1 or 2.
void intensityTransfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                        std::span<const uint8_t> sets, const ToneCurve& tone,
                        std::span<core::Rgb8> out);
void intensityTransfers(const glm::dvec3& totalRadiance, std::span<const glm::dvec3> transfers,
                        std::span<const uint8_t> sets, const ToneCurve& tone,
                        std::span<core::Rgb16> out);

// Beyond Fig. 4, whose fixed 50/50 split is wrong when most sources are occluded (the
// paper's Fig. 3; docs/fig3.md measures it): each source's drop is taken at the point the
// frame buffer is expected to have reached when that source is subtracted,
//   S_ij = T(L_i - q B_j) - T(L_i - q B_j - L_ij),   B_j = sum_{k<j} L_ik,
// with q the expected occluded share of the sources (e.g. the previous frame's measured
// occlusion). q = 1 is Fig. 4 with one set, exact when every source is occluded; q = 0 is
// each source's drop alone, exact when one is; for a random occluded set of share p the
// sum over it tracks T(L) - T(L - sum L_occluded) best with q near p. Same inputs as
// intensityTransfers() except the sets; throws std::invalid_argument unless 0 <= q <= 1.
void intensityTransfersForOcclusion(const glm::dvec3& totalRadiance,
                                    std::span<const glm::dvec3> transfers, double q,
                                    const ToneCurve& tone, std::span<core::Rgb8> out);
void intensityTransfersForOcclusion(const glm::dvec3& totalRadiance,
                                    std::span<const glm::dvec3> transfers, double q,
                                    const ToneCurve& tone, std::span<core::Rgb16> out);

// The same with one expected occluded share per source (cluster): B_j = sum_{k<j} q_k L_ik.
// With q_k the share of cluster k's sources the previous frame saw occluded at this vertex
// (FrameCompositor::observe), the transfers of the clusters occluded again telescope
// exactly: sum over them of S_ij = T(L_i) - T(L_i - sum of their L_ij) when every q_k is 0
// or 1 and matches, which one share for all clusters achieves only in the full umbra.
// Throws std::invalid_argument on length mismatch or a q_k outside [0, 1].
void intensityTransfersForOcclusions(const glm::dvec3& totalRadiance,
                                     std::span<const glm::dvec3> transfers,
                                     std::span<const double> q, const ToneCurve& tone,
                                     std::span<core::Rgb8> out);
void intensityTransfersForOcclusions(const glm::dvec3& totalRadiance,
                                     std::span<const glm::dvec3> transfers,
                                     std::span<const double> q, const ToneCurve& tone,
                                     std::span<core::Rgb16> out);

}  // namespace penumbra::shadow
