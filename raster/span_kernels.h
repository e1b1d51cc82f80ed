// Per-pixel work over one covered row run [xa, xb) of a triangle (docs/pipeline-spec.md
// §5–7), compiled once per SIMD target plus the scalar reference, all byte-identical.
//
// Row pointers address pixel x = 0 of the row. SIMD targets touch whole vectors aligned to
// their lane count (at most 16 pixels) and rewrite lanes outside the run with their old
// values, so callers must own every pixel of [floor16(xa), ceil16(xb)) of that row: tiles
// are multiples of 16 pixels wide and rows are padded (spec §8).
#pragma once

#include <cstdint>

#include "raster/triangle_setup.h"
#include "simd/targets.h"

namespace penumbra::raster {

inline constexpr uint32_t kNoSurface = 0xFFFFFFFEu;  // id of pixels no static triangle covers
inline constexpr uint32_t kObjectId = 0xFFFFFFFFu;   // id of pixels a synthetic object covers

// Where a pixel's receiver point falls in one pass's shadow map (spec §7).
struct ShadowLookup {
  float p[16];       // camera window space -> light texel space, row-major
  const float* map;  // size*size depths, row 0 first
  int32_t size;
  float bias;
  bool pcf2x2;
};

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
  // z < depth: colour, depth and id = kObjectId (spec §6 step 3). Returns pixels written.
  uint32_t (*colourLess)(uint8_t* rgba, float* depth, uint32_t* id, int32_t xa, int32_t xb,
                         int32_t y, const SpanPlanes& planes);
  // The mask-and-subtract pass (spec §6 step 4) runs in two kernels per tile and pass:
  //
  // 1. Per receiver run: where id == triangleId, s = S packed as r | g << 8 | b << 16
  //    (spec §5). Returns how many pixels matched. A pass lists each triangle once
  //    (validateFrame), so no pixel is written twice in one pass.
  uint32_t (*interpolateS)(uint32_t* s, const uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                           const SpanPlanes& planes, uint32_t triangleId);
  // 2. For rows y0 <= y < y1 and xa[y - y0] <= x < xb[y - y0]: where s != 0,
  //    rgb = max(rgb - round(S * M / 255), 0) with M from `lookup` (spec §7); then s = 0,
  //    so the scratch buffer is clean for the next pass. S = 0 subtracts nothing, so
  //    skipping unmarked pixels is exact. Pointers address pixel (0, 0); rows are `stride`
  //    pixels apart.
  void (*shadeRows)(uint8_t* rgba, const float* depth, uint32_t* s, size_t stride, int32_t y0,
                    int32_t y1, const int32_t* xa, const int32_t* xb, const ShadowLookup& lookup);
};

// The kernels of `isa`; the caller checks simd::isSupported(isa).
const SpanKernels& spanKernelsFor(simd::Isa isa);

// The scalar reference (raster/span_kernels_scalar.cpp).
const SpanKernels& scalarSpanKernels();

}  // namespace penumbra::raster
