// Per-pixel work over one covered row run [xa, xb) of a triangle (docs/pipeline-spec.md
// §5–7), compiled once per SIMD target plus the scalar reference, all byte-identical.
//
// Row pointers address pixel x = 0 of the row. SIMD targets touch whole vectors aligned to
// their lane count (at most 16 pixels) and rewrite lanes outside the run with their old
// values, so callers must own every pixel of [floor16(xa), ceil16(xb)) of that row: tiles
// are multiples of 16 pixels wide and rows are padded (spec §8).
#pragma once

#include <cstdint>
#include <utility>

#include "raster/frame_trace.h"
#include "raster/shadow_map.h"
#include "raster/triangle_setup.h"
#include "simd/targets.h"

namespace penumbra::raster {

inline constexpr uint32_t kNoSurface = 0xFFFFFFFEu;  // id of pixels no static triangle covers
// Pixels of synthetic objects hold kObjectBase + the object triangle's index in the frame
// (objects' triangles counted in order), so passes can shadow objects too (§7.2).
inline constexpr uint32_t kObjectBase = 0x80000000u;

// Where a pixel's receiver point falls in one pass's shadow map (spec §7).
struct ShadowLookup {
  float p[16];       // camera window space -> light texel space, row-major
  const float* map;  // texel (0, 0); texel (i, j) at map[j * stride + i] (see ShadowMap)
  int32_t size;
  int32_t stride;
  float bias;
  bool pcf2x2;
  // Optional (may be null): ShadowMap::blocks(). Kernels may answer M = 0 for lanes whose
  // block is zero (all their texels are +inf, so nothing occludes: the same M).
  const uint32_t* blocks = nullptr;
  int32_t blocksPerRow = 0;
  // Area-light penumbrae (spec §7) when penumbraScale > 0: ShadowMap::sumCoverage's counts,
  // their rectangle [coverageX0, coverageX1] x [coverageY0, coverageY1] (texels, even
  // bounds), its blocker cells' sums (ShadowMap::blockers) and the nearest and farthest
  // written depths. `blocks` still serves the lanes the 2x2 PCF answers.
  float penumbraScale = 0;
  float nearest = 0;
  float farthest = 0;
  const int32_t* coverage = nullptr;
  int32_t coverageStride = 0;
  int32_t coverageX0 = 0, coverageY0 = 0, coverageX1 = 0, coverageY1 = 0;
  const uint32_t* blockers = nullptr;
  int32_t blockerStride = 0;
};

// An area-penumbra lookup of scale K (spec §7) into `map`, after its sumCoverage.
inline void setAreaPenumbra(ShadowLookup& lookup, const ShadowMap& map, float scale) {
  const ShadowMap::Rect& r = map.coverageRect();
  lookup.penumbraScale = scale;
  lookup.nearest = map.nearest();
  lookup.farthest = map.farthest();
  lookup.coverage = map.coverage();
  lookup.coverageStride = map.coverageStride();
  lookup.coverageX0 = r.x0;
  lookup.coverageY0 = r.y0;
  lookup.coverageX1 = r.x1;
  lookup.coverageY1 = r.y1;
  lookup.blockers = map.blockers();
  lookup.blockerStride = map.blockerStride();
}

// One triangle's interpolants, with the plane origin (ox, oy) of spec §5.
struct SpanPlanes {
  DepthPlane depth;
  AttributePlane rgb[3];
  int32_t ox, oy;
};

struct SpanKernels {
  // z < depth: depth = z; and, if `id` is not null, id = triangleId (spec §6 steps 1–2).
  // Returns how many pixels passed.
  uint32_t (*depthLess)(float* depth, uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                        const SpanPlanes& planes, uint32_t triangleId);
  // depthLess over every covered run of `t` (rows are `stride` pixels apart, pointers
  // address pixel (0, 0)): one call per triangle keeps the per-row cost to the exact row
  // stepping of RowWalker. Returns how many pixels passed.
  uint32_t (*depthTriangle)(float* depth, uint32_t* id, size_t stride, const SetupTriangle& t,
                            uint32_t triangleId);
  // z < depth: colour, depth and id = objectId (spec §6 step 3). Returns pixels written.
  uint32_t (*colourLess)(uint8_t* rgba, float* depth, uint32_t* id, int32_t xa, int32_t xb,
                         int32_t y, const SpanPlanes& planes, uint32_t objectId);
  // The mask-and-subtract passes (spec §6 step 4) run as three kernels, using the
  // composition rule of spec §8 (subtract the per-pass amounts' sum once):
  //
  // 1. Per receiver run of one pass: where id == triangleId, s = S packed as
  //    r | g << 8 | b << 16 (spec §5). Returns how many pixels matched. A pass lists each
  //    triangle once (validateFrame), so no pixel is written twice in one pass.
  uint32_t (*interpolateS)(uint32_t* s, const uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                           const SpanPlanes& planes, uint32_t triangleId);
  // 2. Once per pass, for rows y0 <= y < y1 and xa[y - y0] <= x < xb[y - y0]: where s != 0,
  //    acc_c += round(S_c * M / 255) for c = r, g, b with M from `lookup` (spec §7); then
  //    s = 0, leaving the scratch clean. S = 0 adds nothing, so skipping unmarked pixels is
  //    exact. `acc` holds three planes (r, g, b) of `planeSize` u16 each; pointers address
  //    pixel (0, 0) and rows are `stride` pixels apart.
  void (*accumulateRows)(const float* depth, uint32_t* s, uint16_t* acc, size_t planeSize,
                         size_t stride, int32_t y0, int32_t y1, const int32_t* xa,
                         const int32_t* xb, const ShadowLookup& lookup);
  // 3. Per row run: out = max(base - sum of the `count` accumulators, 0) per colour
  //    channel, alpha from base; the accumulators are zeroed. Pointers address pixel x = 0
  //    of the row; acc[i] is accumulator i's r plane at that row.
  void (*subtractAccumulated)(uint8_t* out, const uint8_t* base, uint16_t* const* acc, int count,
                              size_t planeSize, int32_t xa, int32_t xb);
  // 1 over all rows of one receiver (sub-)triangle, in one call: rows y0 <= y < y1 with
  // runs[y - y0] = {xa, xb} (empty when xa >= xb), `stride` pixels apart, pointers at pixel
  // (0, 0). The same s as interpolateS on every run; for each row where some pixel matched,
  // begin[y] = min(begin[y], xa) and end[y] = max(end[y], xb). Returns the pixels matched.
  // (One call per row cost more than the pixels of the short runs.)
  uint32_t (*interpolateRuns)(uint32_t* s, const uint32_t* id, size_t stride, int32_t y0,
                              int32_t y1, const std::pair<int32_t, int32_t>* runs,
                              const SpanPlanes& planes, uint32_t triangleId, int32_t* begin,
                              int32_t* end);
  // 1 for fixed-point accumulation (Accumulation::kFixed8_8, spec §5 and §8): the same,
  // but S in 8.8 levels ((v + 0x80) >> 8, at most 255 * 256) into three u16 planes r, g, b
  // (`s`, `s + planeSize`, `s + 2 * planeSize`, laid out like the sums).
  uint32_t (*interpolateRunsFine)(uint16_t* s, size_t planeSize, const uint32_t* id, size_t stride,
                                  int32_t y0, int32_t y1, const std::pair<int32_t, int32_t>* runs,
                                  const SpanPlanes& planes, uint32_t triangleId, int32_t* begin,
                                  int32_t* end);
  // 2 and 3 for fixed-point accumulation: 2 reads interpolateRunsFine's planes and adds
  // round(S_c * W / 65536) (the amount in 1/256 levels; W the occluded weight of spec §7)
  // with saturation at 65535, clearing the planes; 3 subtracts simd::fixed8_8Levels(sum of
  // the accumulators).
  void (*accumulateRowsFine)(const float* depth, uint16_t* s, uint16_t* acc, size_t planeSize,
                             size_t stride, int32_t y0, int32_t y1, const int32_t* xa,
                             const int32_t* xb, const ShadowLookup& lookup);
  void (*subtractAccumulatedFixed8_8)(uint8_t* out, const uint8_t* base, uint16_t* const* acc,
                                      int count, size_t planeSize, int32_t xa, int32_t xb);
  // 3 for linear accumulation (Accumulation::kLinear, spec §8): per colour channel, with
  // the accumulators' sum t clamped to 65280 and q = (t + 64) >> 7 in [0, 510],
  // out = table[base * kShadeSteps + q]; alpha from base; the accumulators are zeroed.
  // `table` holds kShadeCodes * kShadeSteps entries and 3 readable bytes after them (SIMD
  // targets fetch 4 bytes per lookup).
  void (*shadeAccumulatedLinear)(uint8_t* out, const uint8_t* base, uint16_t* const* acc, int count,
                                 size_t planeSize, int32_t xa, int32_t xb, const uint8_t* table);
};

// The kernels of `isa`; the caller checks simd::isSupported(isa).
const SpanKernels& spanKernelsFor(simd::Isa isa);

// The scalar reference (raster/span_kernels_scalar.cpp).
const SpanKernels& scalarSpanKernels();

}  // namespace penumbra::raster
