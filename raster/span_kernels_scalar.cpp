// The scalar reference of raster/span_kernels.h: docs/pipeline-spec.md line by line.
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "core/colour.h"
#include "raster/frame_trace.h"
#include "raster/span_kernels.h"
#include "simd/u8_ops.h"

namespace penumbra::raster {
namespace {

float depthAt(const DepthPlane& p, float fx, float fy) {
  return (p.z00 + p.dzdx * fx) + p.dzdy * fy;  // spec §5
}

uint8_t attributeAt(const AttributePlane& p, uint32_t fx, uint32_t fy) {
  const uint32_t v = p.c + p.gx * fx + p.gy * fy;  // modulo 2^32, spec §5
  const int32_t a = static_cast<int32_t>(v + 0x8000u) >> 16;
  return static_cast<uint8_t>(std::clamp(a, 0, 255));
}

// The same in 8.8 levels (spec §5, fixed8_8).
uint16_t attributeFineAt(const AttributePlane& p, uint32_t fx, uint32_t fy) {
  const uint32_t v = p.c + p.gx * fx + p.gy * fy;
  const int32_t a = static_cast<int32_t>(v + 0x80u) >> 8;
  return static_cast<uint16_t>(std::clamp(a, 0, int32_t{core::kMaxFineLevel}));
}

bool occludes(const ShadowLookup& s, int32_t i, int32_t j, float d) {
  return i >= 0 && i < s.size && j >= 0 && j < s.size &&
         d > s.map[ptrdiff_t{j} * s.stride + i] + s.bias;
}

// Written texels' area in [0, X / 64] x [0, Y / 64] texels, in 1/4096 texel² (spec §7's C):
// the counts N bilinear in 1/64 texel, X and Y clamped to the counts' rectangle (N is 0
// before it and constant past it, so the clamp changes no value).
int32_t coveredArea(const ShadowLookup& s, int32_t x, int32_t y) {
  x = std::clamp(x, s.coverageX0 * kPenumbraSubtexels, s.coverageX1 * kPenumbraSubtexels) -
      s.coverageX0 * kPenumbraSubtexels;
  y = std::clamp(y, s.coverageY0 * kPenumbraSubtexels, s.coverageY1 * kPenumbraSubtexels) -
      s.coverageY0 * kPenumbraSubtexels;
  const int32_t i = x >> 6, a = x & 63, j = y >> 6, b = y & 63;
  const int32_t* n = s.coverage + ptrdiff_t{j} * s.coverageStride + i;
  const int32_t* below = n + s.coverageStride;
  return (n[0] * (64 - a) + n[1] * a) * (64 - b) + (below[0] * (64 - a) + below[1] * a) * b;
}

// Spec §7's blocker search around (u, v) with half-width h: the written texels of the cells
// that hold columns floor(u - h) ... floor(u + h) and the same rows, and the sum of their
// quantized depths, which the modular sums give exactly (a box's sum is below 2^31). The
// texel bounds are clamped to the rectangle's by comparisons (NaN lands on its corner: no
// cell).
struct Blockers {
  int32_t count;
  int32_t depthSum;
};
Blockers blockersAround(const ShadowLookup& s, float u, float v, float h) {
  // Texel bounds clamped to the rectangle's and made relative to its (even) corner.
  auto texel = [](float f, int32_t lo, int32_t hi) {
    const float l = static_cast<float>(lo), g = static_cast<float>(hi);
    return static_cast<int32_t>(f > l ? (f < g ? f : g) : l) - lo;
  };
  static_assert(kBlockerCell == 2, "cells are texel pairs");
  const int32_t a0 = texel(std::floor(u - h), s.coverageX0, s.coverageX1) / 2;
  const int32_t b0 = texel(std::floor(v - h), s.coverageY0, s.coverageY1) / 2;
  const int32_t a1 = (texel(std::floor(u + h) + 1.0f, s.coverageX0, s.coverageX1) + 1) / 2;
  const int32_t b1 = (texel(std::floor(v + h) + 1.0f, s.coverageY0, s.coverageY1) + 1) / 2;
  auto at = [&](int32_t a, int32_t b) {
    return s.blockers + 2 * (ptrdiff_t{b} * s.blockerStride + a);
  };
  const uint32_t* p00 = at(a0, b0);
  const uint32_t* p10 = at(a1, b0);
  const uint32_t* p01 = at(a0, b1);
  const uint32_t* p11 = at(a1, b1);
  const uint32_t count = p11[0] - p10[0] - p01[0] + p00[0];
  const uint32_t sum = p11[1] - p10[1] - p01[1] + p00[1];
  return {static_cast<int32_t>(count), static_cast<int32_t>(sum)};
}

// The penumbra half-width K (d - mean blocker depth) of found blockers (count > 0).
float penumbraOf(const ShadowLookup& s, float d, Blockers found) {
  const float blocker =
      static_cast<float>(found.depthSum) / static_cast<float>(found.count) * (1.0f / kDepthQuantum);
  return s.penumbraScale * (d - blocker);
}

// The area-light lookup of spec §7, or -1 where the 2x2 PCF answers instead.
int32_t areaPenumbraAt(const ShadowLookup& s, float u, float v, float d) {
  if (!(d > s.farthest + s.bias)) return -1;  // among the occluder's depths: contact
  auto clampHalf = [](float h, float hi) { return h > 1.0f ? (h < hi ? h : hi) : 1.0f; };
  const float r = clampHalf(s.penumbraScale * (d - s.nearest), kMaxPenumbraHalfWidth);
  const float size = static_cast<float>(s.size);
  // A search box wholly outside the map (or NaN) finds no blocker.
  if (!(u + r >= 0.0f && u - r < size && v + r >= 0.0f && v - r < size)) return 0;
  const Blockers found = blockersAround(s, u, v, r);
  if (found.count == 0) return 0;
  // The first estimate, searched over every blocker the light can see past; then again over
  // the blockers within that estimate's box.
  float t = penumbraOf(s, d, found);
  const Blockers near = blockersAround(s, u, v, clampHalf(t, r));
  if (near.count > 0) t = penumbraOf(s, d, near);
  if (!(t > kMinPenumbraHalfWidth)) return -1;
  const float w = t < r ? t : r;
  const float sub = static_cast<float>(kPenumbraSubtexels), limit = size * sub;
  const float fx0 = std::floor((u - w) * sub), fx1 = std::floor((u + w) * sub);
  const float fy0 = std::floor((v - w) * sub), fy1 = std::floor((v + w) * sub);
  auto clampSub = [&](float f) {
    return static_cast<int32_t>(f > 0.0f ? (f < limit ? f : limit) : 0.0f);
  };
  const int32_t x0 = clampSub(fx0), x1 = clampSub(fx1), y0 = clampSub(fy0), y1 = clampSub(fy1);
  const int32_t box = coveredArea(s, x1, y1) - coveredArea(s, x0, y1) - coveredArea(s, x1, y0) +
                      coveredArea(s, x0, y0);
  const float area = (fx1 - fx0) * (fy1 - fy0);
  // NOLINTNEXTLINE(bugprone-incorrect-roundings): trunc(x + 0.5) is the spec's rounding
  const int32_t weight = static_cast<int32_t>(static_cast<float>(box) / area * 65536.0f + 0.5f);
  return std::min(weight, 65536);
}

// The occluded weight W in [0, 65536] of spec §7 (M = round(255 W / 65536)).
uint32_t coverageAt(const ShadowLookup& s, float sx, float sy, float z) {
  const float* p = s.p;
  const float q0 = ((p[0] * sx + p[1] * sy) + p[2] * z) + p[3];
  const float q1 = ((p[4] * sx + p[5] * sy) + p[6] * z) + p[7];
  const float q2 = ((p[8] * sx + p[9] * sy) + p[10] * z) + p[11];
  const float q3 = ((p[12] * sx + p[13] * sy) + p[14] * z) + p[15];
  if (!(q3 > 0.0f)) return 0;
  const float u = q0 / q3, v = q1 / q3, d = q2 / q3;
  const float size = static_cast<float>(s.size);
  if (!s.pcf2x2) {
    if (!(u >= 0.0f && u < size && v >= 0.0f && v < size)) return 0;
    return occludes(s, static_cast<int32_t>(u), static_cast<int32_t>(v), d) ? 65536u : 0u;
  }
  if (s.penumbraScale > 0) {
    const int32_t area = areaPenumbraAt(s, u, v, d);
    if (area >= 0) return static_cast<uint32_t>(area);
  }
  const float up = u - 0.5f, vp = v - 0.5f;
  if (!(up > -1.0f && up < size && vp > -1.0f && vp < size)) return 0;
  const float fu = std::floor(up), fv = std::floor(vp);
  const int32_t i = static_cast<int32_t>(fu), j = static_cast<int32_t>(fv);
  // The weights are the spec's (docs/pipeline-spec.md): trunc(f * 256 + 0.5) in float for
  // f = up - fu in [0, 1), which every ISA's kernel computes the same way; lround would be
  // another rounding (it differs where the float sum rounds up), so the check is silenced.
  // NOLINTNEXTLINE(bugprone-incorrect-roundings)
  const int32_t wu = static_cast<int32_t>((up - fu) * 256.0f + 0.5f);
  // NOLINTNEXTLINE(bugprone-incorrect-roundings)
  const int32_t wv = static_cast<int32_t>((vp - fv) * 256.0f + 0.5f);
  const int32_t sum = (occludes(s, i, j, d) ? (256 - wu) * (256 - wv) : 0) +
                      (occludes(s, i + 1, j, d) ? wu * (256 - wv) : 0) +
                      (occludes(s, i, j + 1, d) ? (256 - wu) * wv : 0) +
                      (occludes(s, i + 1, j + 1, d) ? wu * wv : 0);
  return static_cast<uint32_t>(sum);
}

uint32_t depthLess(float* depth, uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                   const SpanPlanes& planes, uint32_t triangleId) {
  uint32_t passed = 0;
  const float fy = static_cast<float>(y - planes.oy);
  for (int32_t x = xa; x < xb; ++x) {
    const float z = depthAt(planes.depth, static_cast<float>(x - planes.ox), fy);
    if (z < depth[x]) {
      depth[x] = z;
      if (id != nullptr) id[x] = triangleId;
      ++passed;
    }
  }
  return passed;
}

uint32_t depthTriangle(float* depth, uint32_t* id, size_t stride, const SetupTriangle& t,
                       uint32_t triangleId) {
  const SpanPlanes planes{t.depth, {}, t.minX, t.minY};
  uint32_t passed = 0;
  forEachRun(t, t.minX, t.minY, t.maxX, t.maxY, false, [&](int32_t y, int32_t xa, int32_t xb) {
    const size_t row = stride * static_cast<size_t>(y);
    passed +=
        depthLess(depth + row, id == nullptr ? nullptr : id + row, xa, xb, y, planes, triangleId);
  });
  return passed;
}

uint32_t colourLess(uint8_t* rgba, float* depth, uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                    const SpanPlanes& planes, uint32_t objectId) {
  uint32_t passed = 0;
  const uint32_t fyu = static_cast<uint32_t>(y - planes.oy);
  const float fy = static_cast<float>(y - planes.oy);
  for (int32_t x = xa; x < xb; ++x) {
    const float z = depthAt(planes.depth, static_cast<float>(x - planes.ox), fy);
    if (!(z < depth[x])) continue;
    const uint32_t fxu = static_cast<uint32_t>(x - planes.ox);
    depth[x] = z;
    id[x] = objectId;
    uint8_t* px = rgba + 4 * static_cast<size_t>(x);
    for (int c = 0; c < 3; ++c) px[c] = attributeAt(planes.rgb[c], fxu, fyu);
    px[3] = 255;
    ++passed;
  }
  return passed;
}

uint32_t interpolateS(uint32_t* s, const uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                      const SpanPlanes& planes, uint32_t triangleId) {
  uint32_t matched = 0;
  const uint32_t fyu = static_cast<uint32_t>(y - planes.oy);
  for (int32_t x = xa; x < xb; ++x) {
    if (id[x] != triangleId) continue;
    ++matched;
    const uint32_t fxu = static_cast<uint32_t>(x - planes.ox);
    s[x] = uint32_t{attributeAt(planes.rgb[0], fxu, fyu)} |
           uint32_t{attributeAt(planes.rgb[1], fxu, fyu)} << 8 |
           uint32_t{attributeAt(planes.rgb[2], fxu, fyu)} << 16;
  }
  return matched;
}

// The pass's S per pixel in the scratch: packed whole levels r | g << 8 | b << 16 (u8), or
// three planes of 8.8 levels (fixed8_8).
struct PackedS {
  uint32_t* s;
  bool take(size_t i, std::array<uint32_t, 3>& c) const {
    if (s[i] == 0) return false;
    for (int ch = 0; ch < 3; ++ch) c[ch] = (s[i] >> (8 * ch)) & 0xFFu;
    s[i] = 0;
    return true;
  }
};
struct FineS {
  uint16_t* s;
  size_t planeSize;
  bool take(size_t i, std::array<uint32_t, 3>& c) const {
    for (size_t ch = 0; ch < 3; ++ch) c[ch] = s[planeSize * ch + i];
    if ((c[0] | c[1] | c[2]) == 0) return false;
    for (size_t ch = 0; ch < 3; ++ch) s[planeSize * ch + i] = 0;
    return true;
  }
};

// u8 (PackedS): spec §6 step 4's rounded product per pass (whose sums never reach 65535);
// fixed8_8 (FineS): spec §8's amounts round(S W / 65536) in 1/256 levels, saturating.
template <class In>
void accumulateRowsFrom(const float* depth, In s, uint16_t* acc, size_t planeSize, size_t stride,
                        int32_t y0, int32_t y1, const int32_t* xa, const int32_t* xb,
                        const ShadowLookup& lookup) {
  constexpr bool kFine = std::is_same_v<In, FineS>;
  for (int32_t y = y0; y < y1; ++y) {
    const size_t row = stride * static_cast<size_t>(y);
    const float sy = static_cast<float>(y) + 0.5f;
    for (int32_t x = xa[y - y0]; x < xb[y - y0]; ++x) {
      std::array<uint32_t, 3> sc;
      if (!s.take(row + x, sc)) continue;
      const uint32_t w = coverageAt(lookup, static_cast<float>(x) + 0.5f, sy, depth[row + x]);
      const auto m = static_cast<uint8_t>((255 * w + 32768) >> 16);
      for (int c = 0; c < 3; ++c) {
        const uint32_t amount =
            kFine ? simd::fineAmount(sc[c], w) : simd::productU8(static_cast<uint8_t>(sc[c]), m);
        uint16_t& sum = acc[planeSize * c + row + x];
        sum = static_cast<uint16_t>(std::min<uint32_t>(sum + amount, 65535u));
      }
    }
  }
}

void accumulateRows(const float* depth, uint32_t* s, uint16_t* acc, size_t planeSize, size_t stride,
                    int32_t y0, int32_t y1, const int32_t* xa, const int32_t* xb,
                    const ShadowLookup& lookup) {
  accumulateRowsFrom(depth, PackedS{s}, acc, planeSize, stride, y0, y1, xa, xb, lookup);
}

void accumulateRowsFine(const float* depth, uint16_t* s, uint16_t* acc, size_t planeSize,
                        size_t stride, int32_t y0, int32_t y1, const int32_t* xa, const int32_t* xb,
                        const ShadowLookup& lookup) {
  accumulateRowsFrom(depth, FineS{s, planeSize}, acc, planeSize, stride, y0, y1, xa, xb, lookup);
}

// The accumulators' sum per channel, zeroed, then the pixel's code: u8 subtracts the sum,
// fixed8_8 its whole levels (spec §8), linear looks the clamped share up in `table`.
template <Accumulation kMode>
void finishAccumulated(uint8_t* out, const uint8_t* base, uint16_t* const* acc, int count,
                       size_t planeSize, int32_t xa, int32_t xb, const uint8_t* table) {
  for (int32_t x = xa; x < xb; ++x) {
    for (int c = 0; c < 3; ++c) {
      int32_t total = 0;
      for (int i = 0; i < count; ++i) {
        total += acc[i][planeSize * c + x];
        acc[i][planeSize * c + x] = 0;
      }
      const uint8_t b = base[4 * x + c];
      if constexpr (kMode == Accumulation::kLinear) {
        const int32_t q = (std::min(total, int32_t{core::kMaxFineLevel}) + 64) >> 7;
        out[4 * x + c] = table[size_t{b} * kShadeSteps + size_t(q)];
        continue;
      }
      if (kMode == Accumulation::kFixed8_8) {
        total = static_cast<int32_t>(simd::fixed8_8Levels(uint32_t(total)));
      }
      out[4 * x + c] = static_cast<uint8_t>(std::max(int32_t{b} - total, 0));
    }
    out[4 * x + 3] = base[4 * x + 3];
  }
}

template <Accumulation kMode>
void subtractAccumulated(uint8_t* out, const uint8_t* base, uint16_t* const* acc, int count,
                         size_t planeSize, int32_t xa, int32_t xb) {
  finishAccumulated<kMode>(out, base, acc, count, planeSize, xa, xb, nullptr);
}

// interpolateS over a triangle's rows, into the packed scratch or (fine) the 8.8 planes.
uint32_t interpolateRunsTo(uint32_t* packed, uint16_t* fine, size_t planeSize, const uint32_t* id,
                           size_t stride, int32_t y0, int32_t y1,
                           const std::pair<int32_t, int32_t>* runs, const SpanPlanes& planes,
                           uint32_t triangleId, int32_t* begin, int32_t* end) {
  uint32_t matched = 0;
  for (int32_t y = y0; y < y1; ++y) {
    const auto [xa, xb] = runs[y - y0];
    if (xa >= xb) continue;
    const size_t row = stride * static_cast<size_t>(y);
    uint32_t n = 0;
    if (packed != nullptr) {
      n = interpolateS(packed + row, id + row, xa, xb, y, planes, triangleId);
    } else {
      const uint32_t fy = static_cast<uint32_t>(y - planes.oy);
      for (int32_t x = xa; x < xb; ++x) {
        if (id[row + x] != triangleId) continue;
        ++n;
        const uint32_t fx = static_cast<uint32_t>(x - planes.ox);
        for (size_t c = 0; c < 3; ++c) {
          fine[planeSize * c + row + x] = attributeFineAt(planes.rgb[c], fx, fy);
        }
      }
    }
    if (n == 0) continue;
    matched += n;
    begin[y] = std::min(begin[y], xa);
    end[y] = std::max(end[y], xb);
  }
  return matched;
}

uint32_t interpolateRuns(uint32_t* s, const uint32_t* id, size_t stride, int32_t y0, int32_t y1,
                         const std::pair<int32_t, int32_t>* runs, const SpanPlanes& planes,
                         uint32_t triangleId, int32_t* begin, int32_t* end) {
  return interpolateRunsTo(s, nullptr, 0, id, stride, y0, y1, runs, planes, triangleId, begin, end);
}

uint32_t interpolateRunsFine(uint16_t* s, size_t planeSize, const uint32_t* id, size_t stride,
                             int32_t y0, int32_t y1, const std::pair<int32_t, int32_t>* runs,
                             const SpanPlanes& planes, uint32_t triangleId, int32_t* begin,
                             int32_t* end) {
  return interpolateRunsTo(nullptr, s, planeSize, id, stride, y0, y1, runs, planes, triangleId,
                           begin, end);
}

const SpanKernels kScalar{&depthLess,
                          &depthTriangle,
                          &colourLess,
                          &interpolateS,
                          &accumulateRows,
                          &subtractAccumulated<Accumulation::kU8>,
                          &interpolateRuns,
                          &interpolateRunsFine,
                          &accumulateRowsFine,
                          &subtractAccumulated<Accumulation::kFixed8_8>,
                          &finishAccumulated<Accumulation::kLinear>};

}  // namespace

const SpanKernels& scalarSpanKernels() {
  return kScalar;
}

}  // namespace penumbra::raster
