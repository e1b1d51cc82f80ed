// SIMD targets of raster/span_kernels.h. Each lane computes exactly what the scalar
// reference computes for its pixel: the same IEEE operations in the same order (no FMA,
// no approximate division), integer planes modulo 2^32 (spec §5), so every target gives
// the reference's bytes. tests/span_kernels_test.cpp compares them pixel by pixel.
#include "raster/span_kernels.h"

#include "raster/frame_trace.h"

#include <algorithm>
#include <array>
#include <type_traits>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/span_kernels.cpp"
#include <hwy/cache_control.h>
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "simd/u8_ops-inl.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using VU = hn::Vec<DU>;
using MI = hn::Mask<DI>;

// E0 >= 0 and E1 >= 0 and E2 >= 0 on int32 lanes: the sign bit of E0 | E1 | E2 is clear
// exactly when no value is negative. One compare instead of three compares, three mask
// inversions (Highway 1.0.3 has no integer Ge) and two mask ANDs, which share one port.
HWY_INLINE MI insideEdges(VI e0, VI e1, VI e2) {
  const DI di;
  return hn::Gt(hn::Or(hn::Or(e0, e1), e2), hn::Set(di, -1));
}

// Lane positions and the run mask of the vector starting at aligned x.
struct Chunk {
  VI px;
  MI inRun;
};

HWY_INLINE Chunk chunkAt(int32_t x, int32_t xa, int32_t xb) {
  const DI di;
  const VI px = hn::Add(hn::Set(di, x), hn::Iota(di, 0));
  // px >= xa is px > xa - 1 (xa >= 0: no overflow).
  return {px, hn::And(hn::Gt(px, hn::Set(di, xa - 1)), hn::Lt(px, hn::Set(di, xb)))};
}

HWY_INLINE int32_t alignDown(int32_t x) {
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(DF()));
  return x & ~(lanes - 1);
}

// z = (z00 + dzdx*fx) + dzdy*fy, spec §5.
HWY_INLINE VF depthAt(const DepthPlane& p, VI px, int32_t ox, float fy) {
  const DF df;
  const DI di;
  const VF fx = hn::ConvertTo(df, hn::Sub(px, hn::Set(di, ox)));
  return hn::Add(hn::Add(hn::Set(df, p.z00), hn::Mul(hn::Set(df, p.dzdx), fx)),
                 hn::Set(df, p.dzdy * fy));
}

// clamp((c + gx*fx + gy*fy mod 2^32 + 0x8000) >> 16, 0, 255) as int32 lanes, spec §5.
HWY_INLINE VI attributeAt(const AttributePlane& p, VU fx, uint32_t fy) {
  const DU du;
  const DI di;
  const VU v =
      hn::Add(hn::Add(hn::Set(du, p.c), hn::Mul(hn::Set(du, p.gx), fx)), hn::Set(du, p.gy * fy));
  const VI a = hn::ShiftRight<16>(hn::BitCast(di, hn::Add(v, hn::Set(du, 0x8000u))));
  return hn::Min(hn::Max(a, hn::Zero(di)), hn::Set(di, 255));
}

uint32_t DepthLess(float* depth, uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                   const SpanPlanes& planes, uint32_t triangleId) {
  const DF df;
  const DI di;
  const DU du;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  const float fy = static_cast<float>(y - planes.oy);
  size_t passed = 0;
  for (int32_t x = alignDown(xa); x < xb; x += lanes) {
    const Chunk c = chunkAt(x, xa, xb);
    const VF z = depthAt(planes.depth, c.px, planes.ox, fy);
    const VF old = hn::LoadU(df, depth + x);
    const auto pass = hn::And(hn::RebindMask(df, c.inRun), hn::Lt(z, old));
    hn::StoreU(hn::IfThenElse(pass, z, old), df, depth + x);
    if (id != nullptr) {
      const VU oldId = hn::LoadU(du, id + x);
      hn::StoreU(hn::IfThenElse(hn::RebindMask(du, pass), hn::Set(du, triangleId), oldId), du,
                 id + x);
    }
    passed += hn::CountTrue(df, pass);
    (void)di;
  }
  return static_cast<uint32_t>(passed);
}

// Small triangles (most of an occluder proxy in a 256x256 map cover a few dozen pixels)
// test the three edges per pixel in int32 lanes instead of stepping exact runs per row.
//
// Why int32 is exact here: when the snapped vertices span at most 64 pixels in x and in y,
// |A|, |B| <= 64 * 256 = 2^14, and every pixel centre of the bounding box (or of the
// aligned vector around it, at most 15 pixels further) lies within 2^14 + 2^12 sub-pixel
// units of each vertex, so |E| <= 2 * 2^14 * (2^14 + 2^12) < 2^30. The row value is
// computed in int64 and narrowed exactly; adding A * 256 * dx (|dx| < 80) stays < 2^31.
// The test E - bias >= 0 is then the same as spec §4's, pixel for pixel.
constexpr int32_t kSmallTriangleSpan = 64 * 256;

HWY_INLINE bool isSmall(const SetupTriangle& t) {
  const int32_t x0 = std::min({t.v[0].x, t.v[1].x, t.v[2].x});
  const int32_t x1 = std::max({t.v[0].x, t.v[1].x, t.v[2].x});
  const int32_t y0 = std::min({t.v[0].y, t.v[1].y, t.v[2].y});
  const int32_t y1 = std::max({t.v[0].y, t.v[1].y, t.v[2].y});
  return x1 - x0 <= kSmallTriangleSpan && y1 - y0 <= kSmallTriangleSpan;
}

// Shadow-map triangles at most one vector wide take the block path below however tall they
// are (occluder slivers: a fifth of the map triangles too tall for isSmall are at most 4
// texels wide, 97 rows on average, half of the exact-run path's rows), when int32 is still
// exact: with Sx, Sy the vertices' extents in sub-pixels, |A| <= Sy and |B| <= Sx; the block
// path evaluates E at pixel centres at most Sx + 2^12 from a vertex in x (15 pixels right of
// the bounding box) and Sy + 2^11 in y (a block's rows and the step after the last, at most
// 7 rows below it), so |E| <= 2 Sx Sy + 2^12 Sy + 2^11 Sx + 1 (the bias), which must stay
// below 2^31. isSmall's triangles satisfy it (2^29 + 2^26 + 2^25 + 1).
HWY_INLINE bool narrowInInt32(const SetupTriangle& t, int32_t lanes) {
  if (t.maxX - t.minX > lanes) return false;
  const int64_t sx =
      std::max({t.v[0].x, t.v[1].x, t.v[2].x}) - int64_t{std::min({t.v[0].x, t.v[1].x, t.v[2].x})};
  const int64_t sy =
      std::max({t.v[0].y, t.v[1].y, t.v[2].y}) - int64_t{std::min({t.v[0].y, t.v[1].y, t.v[2].y})};
  return 2 * sx * sy + (sy << 12) + (sx << 11) + 1 < (int64_t{1} << 31);
}

#if HWY_TARGET != HWY_SCALAR
// Rows r of a block live in lanes [r * W, (r + 1) * W), W = Lanes(d) / R: R rows of W
// consecutive floats become one vector.
template <int R, class D>
HWY_INLINE hn::Vec<D> loadRows(D d, const float* row, size_t stride) {
  if constexpr (R == 1) {
    return hn::LoadU(d, row);
  } else {
    const hn::Half<D> dh;
    return hn::Combine(d, loadRows<R / 2>(dh, row + stride * (R / 2), stride),
                       loadRows<R / 2>(dh, row, stride));
  }
}

template <int R, class D>
HWY_INLINE void storeRows(D d, hn::Vec<D> v, float* row, size_t stride) {
  if constexpr (R == 1) {
    hn::StoreU(v, d, row);
  } else {
    const hn::Half<D> dh;
    storeRows<R / 2>(dh, hn::LowerHalf(dh, v), row, stride);
    storeRows<R / 2>(dh, hn::UpperHalf(dh, v), row + stride * (R / 2), stride);
  }
}

// Small triangles of shadow maps, drawn in blocks of R rows x W = lanes / R columns per
// vector, the block's left edge at minX (not aligned): lane l covers pixel
// (x + l mod W, y + l div W). A 16-lane vector holds 4x4 pixels for triangles at most 4
// wide, 2x8 for at most 8, and 1x16 otherwise (then several vectors per row when wider).
// Lanes outside [minX, maxX) x [minY, maxY) are masked and written back unchanged, so the
// caller leaves R - 1 rows and a vector of slack past the map (ShadowMap does).
//
// Same bytes as the reference: the edge values are spec §4's (int32 is exact by the
// bound above, as the block reaches at most 15 pixels right of and R - 1 rows below the
// bounding box); the per-row value is computed in int64 and then stepped by exact int32
// additions; each lane's depth is (z00 + dzdx*fx) + dzdy*fy with the same binary32 fx, fy.
template <int R>
HWY_NOINLINE uint32_t DepthTriangleBlocks(float* depth, size_t stride, const SetupTriangle& t) {
  const DF df;
  const DI di;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  const int32_t w = lanes / R;  // columns per block
  int log2w = 0;
  while ((1 << log2w) < w) ++log2w;
  const VI lane = hn::Iota(di, 0);
  const VI dx = hn::And(lane, hn::Set(di, w - 1));
  const VI dy = hn::ShiftRightSame(lane, log2w);
  const Edge& g0 = t.edges[0];
  const Edge& g1 = t.edges[1];
  const Edge& g2 = t.edges[2];
  // E at lane offsets from the block's corner pixel, and E's step between block rows.
  auto laneOffsets = [&](const Edge& g) {
    return hn::Add(hn::Mul(hn::Set(di, static_cast<int32_t>(g.a * 256)), dx),
                   hn::Mul(hn::Set(di, static_cast<int32_t>(g.b * 256)), dy));
  };
  const VI off0 = laneOffsets(g0), off1 = laneOffsets(g1), off2 = laneOffsets(g2);
  const VI blockStep0 = hn::Set(di, static_cast<int32_t>(g0.b * 256 * R));
  const VI blockStep1 = hn::Set(di, static_cast<int32_t>(g1.b * 256 * R));
  const VI blockStep2 = hn::Set(di, static_cast<int32_t>(g2.b * 256 * R));
  const VF dzdx = hn::Set(df, t.depth.dzdx), dzdy = hn::Set(df, t.depth.dzdy);
  const VF z00 = hn::Set(df, t.depth.z00);
  const VF fyLane = hn::ConvertTo(df, dy);  // y - minY of the block's first row is added below
  const int64_t yc = int64_t{256} * t.minY + 128;
  uint32_t passed = 0;
  for (int32_t x = t.minX; x < t.maxX; x += w) {
    const int64_t xc = int64_t{256} * x + 128;
    auto cornerValue = [&](const Edge& g, const VI& off) {
      return hn::Add(hn::Set(di, static_cast<int32_t>(g.a * xc + g.b * yc + g.c - g.bias)), off);
    };
    VI e0 = cornerValue(g0, off0), e1 = cornerValue(g1, off1), e2 = cornerValue(g2, off2);
    const VI column = hn::Add(dx, hn::Set(di, x - t.minX));
    const MI inColumns = hn::Lt(column, hn::Set(di, t.maxX - t.minX));
    const VF zColumn = hn::Add(z00, hn::Mul(dzdx, hn::ConvertTo(df, column)));
    for (int32_t y = t.minY; y < t.maxY; y += R) {
      MI covered = hn::And(inColumns, insideEdges(e0, e1, e2));
      e0 = hn::Add(e0, blockStep0);
      e1 = hn::Add(e1, blockStep1);
      e2 = hn::Add(e2, blockStep2);
      if (R > 1 && y + R > t.maxY) covered = hn::And(covered, hn::Lt(dy, hn::Set(di, t.maxY - y)));
      // No test for an empty block: whether a row of a sliver's box meets it is a coin toss
      // for the branch predictor, and writing a block back unchanged costs less than the
      // mispredictions did (map samples -8%).
      const VF fy = hn::Add(fyLane, hn::Set(df, static_cast<float>(y - t.minY)));
      const VF z = hn::Add(zColumn, hn::Mul(dzdy, fy));
      float* corner = depth + stride * static_cast<size_t>(y) + x;
      const VF old = loadRows<R>(df, corner, stride);
      const auto pass = hn::And(hn::RebindMask(df, covered), hn::Lt(z, old));
      storeRows<R>(df, hn::IfThenElse(pass, z, old), corner, stride);
      passed += static_cast<uint32_t>(hn::CountTrue(df, pass));
    }
  }
  return passed;
}
#endif

// Large shadow-map triangles as exact row runs: no RowWalker quotient stepping (about 36
// cycles per row) and no edge tests per vector.
//
// With X = 256 x + 128 and dx = x - minX, spec §4's E - bias = Ec + 256 a dx, where Ec is
// the row's value at minX (stepped exactly by 256 b per row). So E - bias >= 0 <=>
// a dx >= T = ceil(-Ec / 256) = -floor(Ec / 256). Each edge bounds the row's run on its own:
// dx >= ceil(T / a) for a > 0, dx <= floor(T / a) for a < 0, all or nothing for a = 0. The
// run [lo, hi) is then exactly the row's covered pixels, and the lanes only mask its last
// vector.
//
// The bounds of several rows at once, one row per binary64 lane, all exact there: snapped
// coordinates lie within 2^22 (spec §3's snapping range), so |a|, |b| <= 2^23, and at pixel
// centres of the bounding box |Ec| <= 2^48 < 2^53; Ec / 256 is exact (a power of two) and
// floor exact. T is clamped to the range whose quotient lies in [-1, width + 1], which
// changes no bound clipped to [0, width]: a smaller (a > 0) or larger (a < 0) T bounds
// nothing there, a larger or smaller one empties the row either way. The quotient is then
// estimated by T * (1 / a), off by less than 2^-39 from T / a, which is an integer or at
// least 1 / |a| >= 2^-23 from one, so its truncation is the exact bound or one off; the
// exact products a * n (|n| <= width + 2 <= 2^13: below 2^36) decide the one step either
// way, as ceilDiv / floorDiv would.
HWY_NOINLINE uint32_t DepthTriangleRuns(float* depth, size_t stride, const SetupTriangle& t) {
  const DF df;
  const DI di;
  const hn::ScalableTag<double> dd;
  const hn::Rebind<int32_t, decltype(dd)> d32;
  using VD = hn::Vec<decltype(dd)>;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  const int32_t rowLanes = static_cast<int32_t>(hn::Lanes(dd));
  const VI lane = hn::Iota(di, 0);
  const VF laneX = hn::ConvertTo(df, lane);
  const VF dzdx = hn::Set(df, t.depth.dzdx), z00 = hn::Set(df, t.depth.z00);
  const int32_t width = t.maxX - t.minX;
  const int64_t xc = int64_t{256} * t.minX + 128;
  const int64_t yc = int64_t{256} * t.minY + 128;
  const VD zero = hn::Zero(dd), one = hn::Set(dd, 1.0), inv256 = hn::Set(dd, 1.0 / 256.0);
  const VD rowOffset = hn::Iota(dd, 0.0), widthD = hn::Set(dd, static_cast<double>(width));
  std::array<int64_t, 3> ec;  // Ec of the first row of the current group
  for (size_t k = 0; k < 3; ++k) {
    const Edge& g = t.edges[k];
    ec[k] = g.a * xc + g.b * yc + g.c - g.bias;
  }
  HWY_ALIGN int32_t first[hn::MaxLanes(decltype(dd)())], end[hn::MaxLanes(decltype(dd)())];
  uint32_t passed = 0;
  for (int32_t y0 = t.minY; y0 < t.maxY; y0 += rowLanes) {
    VD lo = zero, hi = widthD;
    for (size_t k = 0; k < 3; ++k) {
      const Edge& g = t.edges[k];
      const double a = static_cast<double>(g.a);
      const VD av = hn::Set(dd, a);
      const VD rowEc = hn::Add(hn::Set(dd, static_cast<double>(ec[k])),
                               hn::Mul(rowOffset, hn::Set(dd, static_cast<double>(g.b * 256))));
      ec[k] += g.b * 256 * rowLanes;
      const VD bound = hn::Neg(hn::Floor(hn::Mul(rowEc, inv256)));  // T
      if (g.a > 0) {
        const VD tc = hn::Min(hn::Max(bound, hn::Neg(av)), hn::Mul(av, hn::Add(widthD, one)));
        VD n = hn::Trunc(hn::Mul(tc, hn::Set(dd, 1.0 / a)));
        n = hn::IfThenElse(hn::Lt(hn::Mul(av, n), tc), hn::Add(n, one), n);
        n = hn::IfThenElse(hn::Ge(hn::Mul(av, hn::Sub(n, one)), tc), hn::Sub(n, one), n);
        lo = hn::Max(lo, n);  // ceil(T / a)
      } else if (g.a < 0) {
        const VD tc = hn::Min(hn::Max(bound, hn::Mul(av, hn::Add(widthD, one))), hn::Neg(av));
        VD n = hn::Trunc(hn::Mul(tc, hn::Set(dd, 1.0 / a)));
        n = hn::IfThenElse(hn::Lt(hn::Mul(av, n), tc), hn::Sub(n, one), n);
        n = hn::IfThenElse(hn::Ge(hn::Mul(av, hn::Add(n, one)), tc), hn::Add(n, one), n);
        hi = hn::Min(hi, hn::Add(n, one));  // floor(T / a) + 1
      } else {
        hi = hn::IfThenElse(hn::Gt(bound, zero), zero, hi);
      }
    }
    hn::Store(hn::DemoteTo(d32, lo), d32, first);
    hn::Store(hn::DemoteTo(d32, hi), d32, end);
    for (int32_t r = 0; r < rowLanes && y0 + r < t.maxY; ++r) {
      if (first[r] >= end[r]) continue;
      const int32_t y = y0 + r;
      float* row = depth + stride * static_cast<size_t>(y) + t.minX;
      const VF zy = hn::Set(df, t.depth.dzdy * static_cast<float>(y - t.minY));
      const VI last = hn::Set(di, end[r]);
      for (int32_t dx = first[r]; dx < end[r]; dx += lanes) {
        const MI covered = hn::Lt(hn::Add(lane, hn::Set(di, dx)), last);
        const VF fx = hn::Add(laneX, hn::Set(df, static_cast<float>(dx)));
        const VF z = hn::Add(hn::Add(z00, hn::Mul(dzdx, fx)), zy);
        const VF old = hn::LoadU(df, row + dx);
        const auto pass = hn::And(hn::RebindMask(df, covered), hn::Lt(z, old));
        hn::StoreU(hn::IfThenElse(pass, z, old), df, row + dx);
        passed += static_cast<uint32_t>(hn::CountTrue(df, pass));
      }
    }
  }
  return passed;
}

uint32_t DepthTriangle(float* depth, uint32_t* id, size_t stride, const SetupTriangle& t,
                       uint32_t triangleId) {
  const SpanPlanes planes{t.depth, {}, t.minX, t.minY};
  uint32_t passed = 0;
  const bool small = isSmall(t);
#if HWY_TARGET != HWY_SCALAR
  // Shadow maps (no ids) take the block path: one thread owns the whole map, so writing
  // back unchanged lanes past the bounding box is harmless (ShadowMap leaves room for it).
  if (id == nullptr && (small || narrowInInt32(t, static_cast<int32_t>(hn::Lanes(DF()))))) {
    constexpr size_t kMaxLanes = hn::MaxLanes(DF());
    const size_t width = static_cast<size_t>(t.maxX - t.minX), lanes = hn::Lanes(DF());
    if constexpr (kMaxLanes >= 16) {
      if (lanes >= 16 && width * 4 <= lanes) return DepthTriangleBlocks<4>(depth, stride, t);
    }
    if constexpr (kMaxLanes >= 8) {
      if (lanes >= 8 && width * 2 <= lanes) return DepthTriangleBlocks<2>(depth, stride, t);
    }
    return DepthTriangleBlocks<1>(depth, stride, t);
  }
#endif
  if (!small) {
    if (id == nullptr) return DepthTriangleRuns(depth, stride, t);
    forEachRun(t, t.minX, t.minY, t.maxX, t.maxY, false, [&](int32_t y, int32_t xa, int32_t xb) {
      const size_t row = stride * static_cast<size_t>(y);
      passed +=
          DepthLess(depth + row, id == nullptr ? nullptr : id + row, xa, xb, y, planes, triangleId);
    });
    return passed;
  }
  const DF df;
  const DI di;
  const DU du;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  const int32_t xStart = alignDown(t.minX);
  // Vectors stay in named locals: std::array<Vec> would construct them outside Highway's
  // target attributes, which NEON builds reject.
  const Edge& g0 = t.edges[0];
  const Edge& g1 = t.edges[1];
  const Edge& g2 = t.edges[2];
  const VI step0 = hn::Set(di, static_cast<int32_t>(g0.a * 256));  // E(x + 1) - E(x)
  const VI step1 = hn::Set(di, static_cast<int32_t>(g1.a * 256));
  const VI step2 = hn::Set(di, static_cast<int32_t>(g2.a * 256));
  const VI lane = hn::Iota(di, 0);
  const VI advance = hn::Set(di, lanes);
  const int64_t xc = int64_t{256} * xStart + 128;
  auto rowStart = [&](const Edge& g, int64_t yc, VI step) {
    return hn::Add(hn::Set(di, static_cast<int32_t>(g.a * xc + g.b * yc + g.c - g.bias)),
                   hn::Mul(step, lane));
  };
  for (int32_t y = t.minY; y < t.maxY; ++y) {
    const int64_t yc = int64_t{256} * y + 128;
    VI e0 = rowStart(g0, yc, step0);
    VI e1 = rowStart(g1, yc, step1);
    VI e2 = rowStart(g2, yc, step2);
    const size_t row = stride * static_cast<size_t>(y);
    const float fy = static_cast<float>(y - planes.oy);
    for (int32_t x = xStart; x < t.maxX; x += lanes) {
      const Chunk c = chunkAt(x, t.minX, t.maxX);
      const MI covered = hn::And(c.inRun, insideEdges(e0, e1, e2));
      e0 = hn::Add(e0, hn::Mul(step0, advance));
      e1 = hn::Add(e1, hn::Mul(step1, advance));
      e2 = hn::Add(e2, hn::Mul(step2, advance));
      if (hn::AllFalse(di, covered)) continue;
      const VF z = depthAt(planes.depth, c.px, planes.ox, fy);
      const VF old = hn::LoadU(df, depth + row + x);
      const auto pass = hn::And(hn::RebindMask(df, covered), hn::Lt(z, old));
      hn::StoreU(hn::IfThenElse(pass, z, old), df, depth + row + x);
      if (id != nullptr) {
        const VU oldId = hn::LoadU(du, id + row + x);
        hn::StoreU(hn::IfThenElse(hn::RebindMask(du, pass), hn::Set(du, triangleId), oldId), du,
                   id + row + x);
      }
      passed += static_cast<uint32_t>(hn::CountTrue(df, pass));
    }
  }
  return passed;
}

uint32_t ColourLess(uint8_t* rgba, float* depth, uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                    const SpanPlanes& planes, uint32_t objectId) {
  const DF df;
  const DI di;
  const DU du;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  const float fy = static_cast<float>(y - planes.oy);
  const uint32_t fyu = static_cast<uint32_t>(y - planes.oy);
  uint32_t* pixels = reinterpret_cast<uint32_t*>(rgba);
  size_t passed = 0;
  for (int32_t x = alignDown(xa); x < xb; x += lanes) {
    const Chunk c = chunkAt(x, xa, xb);
    const VF z = depthAt(planes.depth, c.px, planes.ox, fy);
    const VF old = hn::LoadU(df, depth + x);
    const auto pass = hn::And(hn::RebindMask(df, c.inRun), hn::Lt(z, old));
    if (hn::AllFalse(df, pass)) continue;
    const auto passU = hn::RebindMask(du, pass);
    const VU fx = hn::BitCast(du, hn::Sub(c.px, hn::Set(di, planes.ox)));
    const VI r = attributeAt(planes.rgb[0], fx, fyu);
    const VI g = attributeAt(planes.rgb[1], fx, fyu);
    const VI b = attributeAt(planes.rgb[2], fx, fyu);
    const VU packed = hn::BitCast(
        du, hn::Or(hn::Or(r, hn::ShiftLeft<8>(g)),
                   hn::Or(hn::ShiftLeft<16>(b), hn::Set(di, static_cast<int32_t>(0xFF000000u)))));
    hn::StoreU(hn::IfThenElse(pass, z, old), df, depth + x);
    hn::StoreU(hn::IfThenElse(passU, hn::Set(du, objectId), hn::LoadU(du, id + x)), du, id + x);
    hn::StoreU(hn::IfThenElse(passU, packed, hn::LoadU(du, pixels + x)), du, pixels + x);
    passed += hn::CountTrue(df, pass);
  }
  return static_cast<uint32_t>(passed);
}

// Does texel (i, j) occlude depth d? Valid lanes have -1 <= i, j <= size, where the map's
// +inf border answers false as spec §7 requires (see ShadowMap); invalid lanes read texel
// (0, 0) and are masked.
HWY_INLINE MI occludes(const ShadowLookup& s, VI i, VI j, VF d, MI valid) {
  const DF df;
  const DI di;
  const VI index = hn::IfThenElseZero(valid, hn::Add(hn::Mul(j, hn::Set(di, s.stride)), i));
  const VF texel = hn::GatherIndex(df, s.map, index);
  return hn::And(valid, hn::RebindMask(di, hn::Gt(d, hn::Add(texel, hn::Set(df, s.bias)))));
}

// The 4-byte elements at `index` and `index + 1` of `base` for every lane (texels of a map,
// coverage counts): one 64-bit gather per half vector, half the gathered elements of two
// 32-bit gathers, same values. Invalid lanes carry index 0 and read elements 0 and 1, which
// the caller masks.
template <class D>
HWY_INLINE void adjacentPairs(D d, const hn::TFromD<D>* base, VI index, hn::Vec<D>& first,
                              hn::Vec<D>& second) {
#if HWY_TARGET == HWY_SCALAR  // one lane: no halves to split (a target we do not dispatch to)
  const DI di;
  first = hn::GatherIndex(d, base, index);
  second = hn::GatherIndex(d, base, hn::Add(index, hn::Set(di, 1)));
#else
  const DU du;
  const hn::Repartition<uint64_t, DU> d64;
  const hn::RebindToSigned<decltype(d64)> di64;
  const hn::Half<DI> dh;
  const VI bytes = hn::ShiftLeft<2>(index);  // byte offsets of 4-byte elements
  const auto* pairs = reinterpret_cast<const uint64_t*>(base);
  const auto lo = hn::GatherOffset(d64, pairs, hn::PromoteTo(di64, hn::LowerHalf(dh, bytes)));
  const auto hi = hn::GatherOffset(d64, pairs, hn::PromoteTo(di64, hn::UpperHalf(dh, bytes)));
  // Little-endian: the even 32-bit lane of each pair is element `index`, the odd one `+ 1`.
  first = hn::BitCast(d, hn::ConcatEven(du, hn::BitCast(du, hi), hn::BitCast(du, lo)));
  second = hn::BitCast(d, hn::ConcatOdd(du, hn::BitCast(du, hi), hn::BitCast(du, lo)));
#endif
}

HWY_INLINE void texelPairs(const ShadowLookup& s, VI index, VF& first, VF& second) {
  adjacentPairs(DF(), s.map, index, first, second);
}

// False when no valid lane's footprint, starting at texel (i, j), can reach a written texel
// (ShadowMap::blocks): then M = 0 without the texel gathers. The block table is a few KB
// and stays in L1, where the map's texels (256 KB) come from L2.
HWY_INLINE bool anyBlockWritten(const ShadowLookup& s, VI i, VI j, MI valid) {
  if (s.blocks == nullptr) return true;
  const DI di;
  const DU du;
  const VI eight = hn::Set(di, 8);
  const VI block =
      hn::Add(hn::Mul(hn::ShiftRight<3>(hn::Add(j, eight)), hn::Set(di, s.blocksPerRow)),
              hn::ShiftRight<3>(hn::Add(i, eight)));
  const VU written = hn::GatherIndex(du, s.blocks, hn::IfThenElseZero(valid, block));
  return !hn::AllFalse(di, hn::And(valid, hn::RebindMask(di, hn::Ne(written, hn::Zero(du)))));
}

// The 2x2 PCF of spec §7 for the lanes of `front` (q3 > 0 and marked); `depth()` gives
// d = q2 / q3, divided only once some lane may see a written texel.
template <class Depth>
HWY_INLINE VI pcf2x2At(const ShadowLookup& s, VF u, VF v, hn::Mask<DF> front, Depth depth) {
  const DF df;
  const DI di;
  const VF size = hn::Set(df, static_cast<float>(s.size));
  const VF half = hn::Set(df, 0.5f), minusOne = hn::Set(df, -1.0f);
  const VF up = hn::Sub(u, half), vp = hn::Sub(v, half);
  const auto inside = hn::And(front, hn::And(hn::And(hn::Gt(up, minusOne), hn::Lt(up, size)),
                                             hn::And(hn::Gt(vp, minusOne), hn::Lt(vp, size))));
  if (hn::AllFalse(df, inside)) return hn::Zero(di);  // no gather for a vector outside the map
  const MI valid = hn::RebindMask(di, inside);
  const VF fu = hn::Floor(hn::IfThenElseZero(inside, up));
  const VF fv = hn::Floor(hn::IfThenElseZero(inside, vp));
  const VI i = hn::ConvertTo(di, fu), j = hn::ConvertTo(di, fv);
  if (!anyBlockWritten(s, i, j, valid)) return hn::Zero(di);
  const VF d = depth();
  const VF k256 = hn::Set(df, 256.0f);
  const VI wu =
      hn::ConvertTo(di, hn::Add(hn::Mul(hn::Sub(hn::IfThenElseZero(inside, up), fu), k256), half));
  const VI wv =
      hn::ConvertTo(di, hn::Add(hn::Mul(hn::Sub(hn::IfThenElseZero(inside, vp), fv), k256), half));
  const VI full = hn::Set(di, 256);
  const VI iu = hn::Sub(full, wu), iv = hn::Sub(full, wv);
  // Texels (i, j) and (i + 1, j) are adjacent in memory (and inside the +inf border for
  // valid lanes), so one 64-bit gather per row fetches both: half the gathered elements of
  // four 32-bit gathers, same values.
  const VF bias = hn::Set(df, s.bias);
  auto occludedPair = [&](VI texelRow, VI& left, VI& right) {
    VF t0, t1;
    texelPairs(s, hn::IfThenElseZero(valid, hn::Add(hn::Mul(texelRow, hn::Set(di, s.stride)), i)),
               t0, t1);
    left = hn::VecFromMask(di, hn::And(valid, hn::RebindMask(di, hn::Gt(d, hn::Add(t0, bias)))));
    right = hn::VecFromMask(di, hn::And(valid, hn::RebindMask(di, hn::Gt(d, hn::Add(t1, bias)))));
  };
  VI o00, o10, o01, o11;
  occludedPair(j, o00, o10);
  occludedPair(hn::Add(j, hn::Set(di, 1)), o01, o11);
  return hn::Add(hn::Add(hn::And(o00, hn::Mul(iu, iv)), hn::And(o10, hn::Mul(wu, iv))),
                 hn::Add(hn::And(o01, hn::Mul(iu, wv)), hn::And(o11, hn::Mul(wu, wv))));
}

// Spec §7's C: the written texels' area in [0, x / 64] x [0, y / 64] texels, in 1/4096
// texel², for x, y in [0, 64 size]; the counts N bilinear in 1/64 texel. The clamp to the
// counts' rectangle changes no value (N is 0 before it and constant past it). Every product
// stays below 2^30: N <= 512² = 2^18 and the weights sum to 64 on each axis.
HWY_INLINE VI coveredAreaAt(const ShadowLookup& s, VI x, VI y) {
  const DI di;
  const VI ox = hn::Set(di, s.coverageX0 * kPenumbraSubtexels);
  const VI oy = hn::Set(di, s.coverageY0 * kPenumbraSubtexels);
  x = hn::Sub(hn::Min(hn::Max(x, ox), hn::Set(di, s.coverageX1 * kPenumbraSubtexels)), ox);
  y = hn::Sub(hn::Min(hn::Max(y, oy), hn::Set(di, s.coverageY1 * kPenumbraSubtexels)), oy);
  const VI mask = hn::Set(di, kPenumbraSubtexels - 1), full = hn::Set(di, kPenumbraSubtexels);
  const VI a = hn::And(x, mask), b = hn::And(y, mask);
  const VI index =
      hn::Add(hn::Mul(hn::ShiftRight<6>(y), hn::Set(di, s.coverageStride)), hn::ShiftRight<6>(x));
  VI n00, n10, n01, n11;
  adjacentPairs(di, s.coverage, index, n00, n10);
  adjacentPairs(di, s.coverage + s.coverageStride, index, n01, n11);
  const VI ia = hn::Sub(full, a), ib = hn::Sub(full, b);
  return hn::Add(hn::Mul(hn::Add(hn::Mul(n00, ia), hn::Mul(n10, a)), ib),
                 hn::Mul(hn::Add(hn::Mul(n01, ia), hn::Mul(n11, a)), b));
}

// Spec §7's blocker search around (u, v) with half-width h: the written texels of the cells
// that hold columns floor(u - h) ... floor(u + h) and the same rows, and their quantized
// depths' sum. The texel bounds are clamped to the rectangle's by comparisons (NaN lanes land on
// its corner: no cell); the tables are modular, as int32 lanes add and subtract, and a
// box's sum is below 2^31. Each cell's count and sum are adjacent: one pair gather per
// corner.
HWY_INLINE void blockersAround(const ShadowLookup& s, VF u, VF v, VF h, VI& count, VI& depthSum) {
  const DF df;
  const DI di;
  // Texel bounds clamped to the rectangle's and made relative to its (even) corner.
  auto texel = [&](VF f, int32_t lo, int32_t hi) {
    const VF l = hn::Set(df, static_cast<float>(lo)), g = hn::Set(df, static_cast<float>(hi));
    return hn::Sub(
        hn::ConvertTo(di, hn::IfThenElse(hn::Gt(f, l), hn::IfThenElse(hn::Lt(f, g), f, g), l)),
        hn::Set(di, lo));
  };
  static_assert(kBlockerCell == 2, "cells are texel pairs");
  const VF one = hn::Set(df, 1.0f);
  const VI vone = hn::Set(di, 1);
  const VI a0 = hn::ShiftRight<1>(texel(hn::Floor(hn::Sub(u, h)), s.coverageX0, s.coverageX1));
  const VI b0 = hn::ShiftRight<1>(texel(hn::Floor(hn::Sub(v, h)), s.coverageY0, s.coverageY1));
  const VI a1 = hn::ShiftRight<1>(
      hn::Add(texel(hn::Add(hn::Floor(hn::Add(u, h)), one), s.coverageX0, s.coverageX1), vone));
  const VI b1 = hn::ShiftRight<1>(
      hn::Add(texel(hn::Add(hn::Floor(hn::Add(v, h)), one), s.coverageY0, s.coverageY1), vone));
  const VI stride = hn::Set(di, s.blockerStride);
  auto at = [&](VI a, VI b) { return hn::ShiftLeft<1>(hn::Add(hn::Mul(b, stride), a)); };
  const int32_t* table = reinterpret_cast<const int32_t*>(s.blockers);
  VI n00, z00, n10, z10, n01, z01, n11, z11;
  adjacentPairs(di, table, at(a0, b0), n00, z00);
  adjacentPairs(di, table, at(a1, b0), n10, z10);
  adjacentPairs(di, table, at(a0, b1), n01, z01);
  adjacentPairs(di, table, at(a1, b1), n11, z11);
  count = hn::Add(hn::Sub(hn::Sub(n11, n10), n01), n00);
  depthSum = hn::Add(hn::Sub(hn::Sub(z11, z10), z01), z00);
}

// The penumbra half-width K (d - mean blocker depth); lanes with count 0 divide by 1.
HWY_INLINE VF penumbraOf(const ShadowLookup& s, VF d, VI count, VI depthSum) {
  const DF df;
  const DI di;
  const VF blocker = hn::Mul(
      hn::Div(hn::ConvertTo(df, depthSum), hn::ConvertTo(df, hn::Max(count, hn::Set(di, 1)))),
      hn::Set(df, 1.0f / kDepthQuantum));
  return hn::Mul(hn::Set(df, s.penumbraScale), hn::Sub(d, blocker));
}

// The area-light lookup of spec §7 for the lanes of `front`: W where it answers (the lanes
// set in `answered`), the 2x2 PCF's lanes left to the caller.
HWY_INLINE VI areaPenumbraAt(const ShadowLookup& s, VF u, VF v, VF d, hn::Mask<DF> front,
                             hn::Mask<DF>& answered) {
  const DF df;
  const DI di;
  // Behind every occluder texel.
  const auto behind = hn::And(front, hn::Gt(d, hn::Set(df, s.farthest + s.bias)));
  answered = behind;
  if (hn::AllFalse(df, behind)) return hn::Zero(di);
  const VF one = hn::Set(df, 1.0f);
  auto clampHalf = [&](VF h, VF hi) {
    return hn::IfThenElse(hn::Gt(h, one), hn::IfThenElse(hn::Lt(h, hi), h, hi), one);
  };
  const VF r = clampHalf(hn::Mul(hn::Set(df, s.penumbraScale), hn::Sub(d, hn::Set(df, s.nearest))),
                         hn::Set(df, kMaxPenumbraHalfWidth));
  // A search box wholly outside the written texels' rectangle finds no blocker (W = 0): the
  // boxes are tested against it, so that a vector of such boxes needs no gathers. The box
  // holds the texels floor(u - r) ... floor(u + r): it meets column x0 when u + r >= x0 and
  // the last column, x1 - 1, when u - r < x1.
  const VF rx0 = hn::Set(df, static_cast<float>(s.coverageX0));
  const VF rx1 = hn::Set(df, static_cast<float>(s.coverageX1));
  const VF ry0 = hn::Set(df, static_cast<float>(s.coverageY0));
  const VF ry1 = hn::Set(df, static_cast<float>(s.coverageY1));
  const auto searched =
      hn::And(behind, hn::And(hn::And(hn::Ge(hn::Add(u, r), rx0), hn::Lt(hn::Sub(u, r), rx1)),
                              hn::And(hn::Ge(hn::Add(v, r), ry0), hn::Lt(hn::Sub(v, r), ry1))));
  if (hn::AllFalse(df, searched)) return hn::Zero(di);
  VI count, depthSum;
  blockersAround(s, u, v, r, count, depthSum);
  const auto found = hn::And(searched, hn::RebindMask(df, hn::Gt(count, hn::Zero(di))));
  if (hn::AllFalse(df, found)) return hn::Zero(di);
  // The first estimate, over every blocker the light can see past; then again over the
  // blockers within that estimate's box.
  VF t = penumbraOf(s, d, count, depthSum);
  blockersAround(s, u, v, clampHalf(t, r), count, depthSum);
  t = hn::IfThenElse(hn::RebindMask(df, hn::Gt(count, hn::Zero(di))),
                     penumbraOf(s, d, count, depthSum), t);
  const auto wide = hn::Gt(t, hn::Set(df, kMinPenumbraHalfWidth));
  // Found blockers but a box within the 2x2 footprint: the PCF answers.
  answered = hn::AndNot(hn::AndNot(wide, found), behind);
  const auto meets = hn::And(found, wide);
  if (hn::AllFalse(df, meets)) return hn::Zero(di);
  const VF zero = hn::Zero(df), size = hn::Set(df, static_cast<float>(s.size));
  u = hn::IfThenElseZero(meets, u);
  v = hn::IfThenElseZero(meets, v);
  const VF w = hn::IfThenElse(meets, hn::IfThenElse(hn::Lt(t, r), t, r), one);
  const VF sub = hn::Set(df, static_cast<float>(kPenumbraSubtexels));
  const VF limit = hn::Mul(size, sub);
  const VF fx0 = hn::Floor(hn::Mul(hn::Sub(u, w), sub)),
           fx1 = hn::Floor(hn::Mul(hn::Add(u, w), sub));
  const VF fy0 = hn::Floor(hn::Mul(hn::Sub(v, w), sub)),
           fy1 = hn::Floor(hn::Mul(hn::Add(v, w), sub));
  // Clamped to [0, 64 size] by comparisons (Min and Max differ across ISAs on NaN).
  auto clampSub = [&](VF f) {
    return hn::ConvertTo(
        di, hn::IfThenElse(hn::Gt(f, zero), hn::IfThenElse(hn::Lt(f, limit), f, limit), zero));
  };
  const VI x0 = clampSub(fx0), x1 = clampSub(fx1), y0 = clampSub(fy0), y1 = clampSub(fy1);
  const VI box = hn::Add(hn::Sub(hn::Sub(coveredAreaAt(s, x1, y1), coveredAreaAt(s, x0, y1)),
                                 coveredAreaAt(s, x1, y0)),
                         coveredAreaAt(s, x0, y0));
  const VF area = hn::Mul(hn::Sub(fx1, fx0), hn::Sub(fy1, fy0));
  const VI weight = hn::ConvertTo(
      di, hn::Add(hn::Mul(hn::Div(hn::ConvertTo(df, box), area), hn::Set(df, 65536.0f)),
                  hn::Set(df, 0.5f)));
  return hn::IfThenElseZero(hn::RebindMask(di, meets), hn::Min(weight, hn::Set(di, 65536)));
}

// The occluded weight W of spec §7 as int32 lanes in [0, 65536] (the mask before its
// scaling: M = round(255 W / 65536)). Lanes outside `marked` (S = 0, which adds nothing) may
// get W = 0 instead of their value.
HWY_INLINE VI coverageAt(const ShadowLookup& s, VF sx, VF sy, VF z, MI marked) {
  const DF df;
  const DI di;
  const float* p = s.p;
  auto row = [&](int r) {
    return hn::Add(
        hn::Add(hn::Add(hn::Mul(hn::Set(df, p[4 * r]), sx), hn::Mul(hn::Set(df, p[4 * r + 1]), sy)),
                hn::Mul(hn::Set(df, p[4 * r + 2]), z)),
        hn::Set(df, p[4 * r + 3]));
  };
  const VF q0 = row(0), q1 = row(1), q3 = row(3);
  const auto front = hn::And(hn::RebindMask(df, marked), hn::Gt(q3, hn::Zero(df)));
  const VF u = hn::Div(q0, q3), v = hn::Div(q1, q3);
  const VF size = hn::Set(df, static_cast<float>(s.size));
  if (!s.pcf2x2) {
    const auto inside = hn::And(front, hn::And(hn::And(hn::Ge(u, hn::Zero(df)), hn::Lt(u, size)),
                                               hn::And(hn::Ge(v, hn::Zero(df)), hn::Lt(v, size))));
    // Often a whole vector of receivers lies outside the light's map (about a third of the
    // showroom's): no division for d and no gather then.
    if (hn::AllFalse(df, inside)) return hn::Zero(di);
    const MI valid = hn::RebindMask(di, inside);
    // Truncation equals floor here: u, v >= 0 in valid lanes; others are masked.
    const VI i = hn::ConvertTo(di, hn::IfThenElseZero(inside, u));
    const VI j = hn::ConvertTo(di, hn::IfThenElseZero(inside, v));
    if (!anyBlockWritten(s, i, j, valid)) return hn::Zero(di);
    const VF d = hn::Div(row(2), q3);
    return hn::IfThenElseZero(occludes(s, i, j, d, valid), hn::Set(di, 65536));
  }
  if (s.penumbraScale > 0) {
    const VF d = hn::Div(row(2), q3);
    hn::Mask<DF> area;
    const VI wide = areaPenumbraAt(s, u, v, d, front, area);
    const auto rest = hn::AndNot(area, front);
    if (hn::AllFalse(df, rest)) return wide;
    return hn::IfThenElse(hn::RebindMask(di, area), wide,
                          pcf2x2At(s, u, v, rest, [&] { return d; }));
  }
  return pcf2x2At(s, u, v, front, [&] { return hn::Div(row(2), q3); });
}

uint32_t InterpolateS(uint32_t* sOut, const uint32_t* id, int32_t xa, int32_t xb, int32_t y,
                      const SpanPlanes& planes, uint32_t triangleId) {
  const DI di;
  const DU du;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(du));
  const uint32_t fyu = static_cast<uint32_t>(y - planes.oy);
  size_t matched = 0;
  for (int32_t x = alignDown(xa); x < xb; x += lanes) {
    const Chunk c = chunkAt(x, xa, xb);
    const auto active = hn::And(hn::RebindMask(du, c.inRun),
                                hn::Eq(hn::LoadU(du, id + x), hn::Set(du, triangleId)));
    if (hn::AllFalse(du, active)) continue;
    matched += hn::CountTrue(du, active);
    const VU fx = hn::BitCast(du, hn::Sub(c.px, hn::Set(di, planes.ox)));
    const VI packed = hn::Or(hn::Or(attributeAt(planes.rgb[0], fx, fyu),
                                    hn::ShiftLeft<8>(attributeAt(planes.rgb[1], fx, fyu))),
                             hn::ShiftLeft<16>(attributeAt(planes.rgb[2], fx, fyu)));
    hn::StoreU(hn::IfThenElse(active, hn::BitCast(du, packed), hn::LoadU(du, sOut + x)), du,
               sOut + x);
  }
  return static_cast<uint32_t>(matched);
}

// Where the pass's S goes per pixel: packed whole levels r | g << 8 | b << 16 (u8
// accumulation), or three planes of 8.8 levels (fixed8_8), `planeSize` u16 apart.
struct PackedS {
  uint32_t* s;
};
struct FineS {
  uint16_t* s;
  size_t planeSize;
};

// InterpolateS over a triangle's rows (see SpanKernels::interpolateRuns and
// interpolateRunsFine). The planes are broadcast once per triangle and the row term once per
// row; v is summed in another order than attributeAt's (c + gy fy + rounding first), which
// wrapping 32-bit addition allows (spec §5), so every lane is the same.
template <class Out>
uint32_t InterpolateRunsTo(Out out, const uint32_t* id, size_t stride, int32_t y0, int32_t y1,
                           const std::pair<int32_t, int32_t>* runs, const SpanPlanes& planes,
                           uint32_t triangleId, int32_t* begin, int32_t* end) {
  constexpr bool kFine = std::is_same_v<Out, FineS>;
  // Whole levels: (v + 0x8000) >> 16 in [0, 255]; 8.8 levels: (v + 0x80) >> 8 in
  // [0, 255 * 256] (spec §5).
  constexpr uint32_t kHalf = kFine ? 0x80u : 0x8000u;
  constexpr int32_t kTop = kFine ? 255 * 256 : 255;
  const DI di;
  const DU du;
  const hn::Rebind<uint16_t, DI> d16;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(du));
  const AttributePlane pr = planes.rgb[0], pg = planes.rgb[1], pb = planes.rgb[2];
  const int32_t ox = planes.ox, oy = planes.oy;
  // Separate vectors, not std::array's of them: see DepthTriangle.
  const VU gxR = hn::Set(du, pr.gx), gxG = hn::Set(du, pg.gx), gxB = hn::Set(du, pb.gx);
  const VU want = hn::Set(du, triangleId);
  const VI zero = hn::Zero(di), top = hn::Set(di, kTop);
  auto channel = [&](VU rowValue, VU g, VU fx) {
    const VI v = hn::BitCast(di, hn::Add(rowValue, hn::Mul(g, fx)));
    return hn::Min(hn::Max(kFine ? hn::ShiftRight<8>(v) : hn::ShiftRight<16>(v), zero), top);
  };
  size_t matched = 0;
  for (int32_t y = y0; y < y1; ++y) {
    const auto [xa, xb] = runs[y - y0];
    if (xa >= xb) continue;
    const size_t row = stride * static_cast<size_t>(y);
    const uint32_t fy = static_cast<uint32_t>(y - oy);
    const VU rowR = hn::Set(du, pr.c + pr.gy * fy + kHalf);
    const VU rowG = hn::Set(du, pg.c + pg.gy * fy + kHalf);
    const VU rowB = hn::Set(du, pb.c + pb.gy * fy + kHalf);
    size_t rowMatched = 0;
    for (int32_t x = alignDown(xa); x < xb; x += lanes) {
      const Chunk c = chunkAt(x, xa, xb);
      const auto active =
          hn::And(hn::RebindMask(du, c.inRun), hn::Eq(hn::LoadU(du, id + row + x), want));
      if (hn::AllFalse(du, active)) continue;
      rowMatched += hn::CountTrue(du, active);
      const VU fx = hn::BitCast(du, hn::Sub(c.px, hn::Set(di, ox)));
      if constexpr (kFine) {
        // Highway 1.0.3 has no mask between lane sizes: blend in 32-bit lanes.
        const MI activeI = hn::RebindMask(di, active);
        const auto store = [&](size_t ch, VI value) {
          uint16_t* o = out.s + out.planeSize * ch + row + x;
          const VI kept = hn::IfThenElse(activeI, value, hn::PromoteTo(di, hn::LoadU(d16, o)));
          hn::StoreU(hn::DemoteTo(d16, kept), d16, o);
        };
        store(0, channel(rowR, gxR, fx));
        store(1, channel(rowG, gxG, fx));
        store(2, channel(rowB, gxB, fx));
      } else {
        const VI packed =
            hn::Or(hn::Or(channel(rowR, gxR, fx), hn::ShiftLeft<8>(channel(rowG, gxG, fx))),
                   hn::ShiftLeft<16>(channel(rowB, gxB, fx)));
        uint32_t* o = out.s + row + x;
        hn::StoreU(hn::IfThenElse(active, hn::BitCast(du, packed), hn::LoadU(du, o)), du, o);
      }
    }
    if (rowMatched == 0) continue;
    matched += rowMatched;
    begin[y] = std::min(begin[y], xa);
    end[y] = std::max(end[y], xb);
  }
  return static_cast<uint32_t>(matched);
}

uint32_t InterpolateRuns(uint32_t* sOut, const uint32_t* id, size_t stride, int32_t y0, int32_t y1,
                         const std::pair<int32_t, int32_t>* runs, const SpanPlanes& planes,
                         uint32_t triangleId, int32_t* begin, int32_t* end) {
  return InterpolateRunsTo(PackedS{sOut}, id, stride, y0, y1, runs, planes, triangleId, begin, end);
}

uint32_t InterpolateRunsFine(uint16_t* sOut, size_t planeSize, const uint32_t* id, size_t stride,
                             int32_t y0, int32_t y1, const std::pair<int32_t, int32_t>* runs,
                             const SpanPlanes& planes, uint32_t triangleId, int32_t* begin,
                             int32_t* end) {
  return InterpolateRunsTo(FineS{sOut, planeSize}, id, stride, y0, y1, runs, planes, triangleId,
                           begin, end);
}

// A vector of a pass's S taken out of the scratch (which is left zero): false, touching
// nothing, when every lane is 0 (S = 0 adds nothing, so skipping it is exact).
HWY_INLINE bool takeS(PackedS in, size_t i, VI& r, VI& g, VI& b) {
  const DU du;
  const VU packed = hn::LoadU(du, in.s + i);
  if (hn::AllTrue(du, hn::Eq(packed, hn::Zero(du)))) return false;
  hn::StoreU(hn::Zero(du), du, in.s + i);
  const VU byteMask = hn::Set(du, 0xFFu);
  r = hn::BitCast(DI(), hn::And(packed, byteMask));
  g = hn::BitCast(DI(), hn::And(hn::ShiftRight<8>(packed), byteMask));
  b = hn::BitCast(DI(), hn::And(hn::ShiftRight<16>(packed), byteMask));
  return true;
}

HWY_INLINE bool takeS(FineS in, size_t i, VI& r, VI& g, VI& b) {
  const DI di;
  const hn::Rebind<uint16_t, DI> d16;
  const auto r16 = hn::LoadU(d16, in.s + i);
  const auto g16 = hn::LoadU(d16, in.s + in.planeSize + i);
  const auto b16 = hn::LoadU(d16, in.s + 2 * in.planeSize + i);
  if (hn::AllTrue(d16, hn::Eq(hn::Or(hn::Or(r16, g16), b16), hn::Zero(d16)))) return false;
  for (size_t ch = 0; ch < 3; ++ch) hn::StoreU(hn::Zero(d16), d16, in.s + in.planeSize * ch + i);
  r = hn::PromoteTo(di, r16);
  g = hn::PromoteTo(di, g16);
  b = hn::PromoteTo(di, b16);
  return true;
}

// The pass's amounts into the sums: u8 (PackedS) adds spec §6 step 4's rounded product
// round(S M / 255) per pass; fixed8_8 (FineS) adds spec §8's round(S W / 65536) in 1/256
// levels, saturating.
template <class In>
void AccumulateRowsFrom(const float* depth, In s, uint16_t* acc, size_t planeSize, size_t stride,
                        int32_t y0, int32_t y1, const int32_t* xaRow, const int32_t* xbRow,
                        const ShadowLookup& lookup) {
  constexpr bool kFine = std::is_same_v<In, FineS>;
  const DF df;
  const DI di;
  const DU du;
  const hn::Rebind<uint16_t, DI> d16;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(df));
  for (int32_t y = y0; y < y1; ++y) {
    const int32_t xa = xaRow[y - y0], xb = xbRow[y - y0];
    const size_t row = stride * static_cast<size_t>(y);
    // The sums (three u16 planes, 1.8 MB per thread at 640x480) and the depth buffer do not
    // stay in L2 across passes, and a pass's runs are too short per row for the hardware
    // prefetchers: fetch the next row's lines while this row computes masks. Prefetches
    // change no value.
    if (y + 1 < y1 && xaRow[y + 1 - y0] < xbRow[y + 1 - y0]) {
      const size_t next = row + stride;
      const size_t first = static_cast<size_t>(xaRow[y + 1 - y0]) & ~size_t{15};
      const size_t last = static_cast<size_t>(xbRow[y + 1 - y0]);
      for (size_t x = first; x < last; x += 16) {
        hwy::Prefetch(depth + next + x);
        if ((x & 31) == 0 || x == first) {
          for (size_t ch = 0; ch < 3; ++ch) hwy::Prefetch(acc + planeSize * ch + next + x);
        }
      }
    }
    const VF sy = hn::Set(df, static_cast<float>(y) + 0.5f);
    for (int32_t x = alignDown(xa); x < xb; x += lanes) {
      // Outside [xa, xb) s is 0 too (the scratch is kept clean), so no run mask is needed.
      VI sR, sG, sB;
      if (!takeS(s, row + x, sR, sG, sB)) continue;
      const VI px = hn::Add(hn::Set(di, x), hn::Iota(di, 0));
      const VF sx = hn::Add(hn::ConvertTo(df, px), hn::Set(df, 0.5f));
      const MI marked = hn::Ne(hn::Or(hn::Or(sR, sG), sB), hn::Zero(di));
      const VI w = coverageAt(lookup, sx, sy, hn::LoadU(df, depth + row + x), marked);
      // W = 0 adds 0: leave the sums alone. Most vectors of a pass are lit or outside the
      // map, so this saves most of the sweep's memory traffic.
      if (hn::AllTrue(di, hn::Eq(w, hn::Zero(di)))) continue;
      // M = round(255 W / 65536) (spec §7); 255 W + 32768 < 2^24.
      const VI m = hn::ShiftRight<16>(hn::Add(hn::Mul(w, hn::Set(di, 255)), hn::Set(di, 32768)));
      const auto add = [&](size_t ch, VI sValue) {
        uint16_t* plane = acc + planeSize * ch + row + x;
        // Unmarked lanes have S = 0 and add 0. u8 sums stay <= 65535 (at most 257 passes);
        // fixed-point sums saturate there (DemoteTo), as spec §8 allows.
        const VI amount =
            kFine ? hn::BitCast(di, simd::HWY_NAMESPACE::FineAmount(du, hn::BitCast(du, sValue),
                                                                    hn::BitCast(du, w)))
                  : simd::HWY_NAMESPACE::ProductU8(di, sValue, m);
        const VI sum = hn::Add(hn::PromoteTo(di, hn::LoadU(d16, plane)), amount);
        hn::StoreU(hn::DemoteTo(d16, sum), d16, plane);
      };
      add(0, sR);
      add(1, sG);
      add(2, sB);
    }
  }
}

void AccumulateRows(const float* depth, uint32_t* s, uint16_t* acc, size_t planeSize, size_t stride,
                    int32_t y0, int32_t y1, const int32_t* xa, const int32_t* xb,
                    const ShadowLookup& lookup) {
  AccumulateRowsFrom(depth, PackedS{s}, acc, planeSize, stride, y0, y1, xa, xb, lookup);
}

void AccumulateRowsFine(const float* depth, uint16_t* s, uint16_t* acc, size_t planeSize,
                        size_t stride, int32_t y0, int32_t y1, const int32_t* xa, const int32_t* xb,
                        const ShadowLookup& lookup) {
  AccumulateRowsFrom(depth, FineS{s, planeSize}, acc, planeSize, stride, y0, y1, xa, xb, lookup);
}

// See the scalar finishAccumulated: u8 subtracts the accumulators' sum, fixed8_8 its whole
// levels, linear looks the clamped share up in the shade table (spec §8).
template <Accumulation kMode>
void FinishAccumulated(uint8_t* out, const uint8_t* base, uint16_t* const* acc, int count,
                       size_t planeSize, int32_t xa, int32_t xb, const uint8_t* table) {
  const DI di;
  const DU du;
  const hn::Rebind<uint16_t, DI> d16;
  const int32_t lanes = static_cast<int32_t>(hn::Lanes(di));
  const VU byteMask = hn::Set(du, 0xFFu);
  uint32_t* outPixels = reinterpret_cast<uint32_t*>(out);
  const uint32_t* basePixels = reinterpret_cast<const uint32_t*>(base);
  for (int32_t x = alignDown(xa); x < xb; x += lanes) {
    const Chunk c = chunkAt(x, xa, xb);
    const VU old = hn::LoadU(du, basePixels + x);
    VU result = hn::And(old, hn::Set(du, 0xFF000000u));
    for (int ch = 0; ch < 3; ++ch) {
      VI total = hn::Zero(di);
      for (int i = 0; i < count; ++i) {
        uint16_t* plane = acc[i] + planeSize * ch + x;
        const VI values = hn::PromoteTo(di, hn::LoadU(d16, plane));
        total = hn::Add(total, values);
        hn::StoreU(hn::DemoteTo(d16, hn::IfThenZeroElse(c.inRun, values)), d16, plane);
      }
      const VI value = hn::BitCast(di, hn::And(hn::ShiftRightSame(old, 8 * ch), byteMask));
      VI left;
      if constexpr (kMode == Accumulation::kLinear) {
        // Entry base * 511 + q, fetched as the 4 bytes starting there (the table is padded),
        // keeping the first (little-endian: the low byte).
        const VI q = hn::ShiftRight<7>(
            hn::Add(hn::Min(total, hn::Set(di, int32_t{core::kMaxFineLevel})), hn::Set(di, 64)));
        const VI index = hn::Add(hn::Mul(value, hn::Set(di, int32_t{kShadeSteps})), q);
        const VI word = hn::GatherOffset(di, reinterpret_cast<const int32_t*>(table), index);
        left = hn::And(word, hn::Set(di, 0xFF));
      } else {
        if (kMode == Accumulation::kFixed8_8) {
          total = simd::HWY_NAMESPACE::Fixed8_8Levels(di, total);
        }
        left = simd::HWY_NAMESPACE::SubtractSaturate(di, value, total);
      }
      result = hn::Or(result, hn::ShiftLeftSame(hn::BitCast(du, left), 8 * ch));
    }
    hn::StoreU(hn::IfThenElse(hn::RebindMask(du, c.inRun), result, hn::LoadU(du, outPixels + x)),
               du, outPixels + x);
  }
}

template <Accumulation kMode>
void SubtractAccumulated(uint8_t* out, const uint8_t* base, uint16_t* const* acc, int count,
                         size_t planeSize, int32_t xa, int32_t xb) {
  FinishAccumulated<kMode>(out, base, acc, count, planeSize, xa, xb, nullptr);
}

const SpanKernels* Table() {
  static const SpanKernels kernels{&DepthLess,
                                   &DepthTriangle,
                                   &ColourLess,
                                   &InterpolateS,
                                   &AccumulateRows,
                                   &SubtractAccumulated<Accumulation::kU8>,
                                   &InterpolateRuns,
                                   &InterpolateRunsFine,
                                   &AccumulateRowsFine,
                                   &SubtractAccumulated<Accumulation::kFixed8_8>,
                                   &FinishAccumulated<Accumulation::kLinear>};
  return &kernels;
}

}  // namespace penumbra::raster::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/target_table.h"

namespace penumbra::raster {

const SpanKernels& spanKernelsFor(simd::Isa isa) {
  if (isa == simd::Isa::kScalar) return scalarSpanKernels();
  return *PENUMBRA_TARGET_TABLE_LOOKUP(Table, isa);
}

}  // namespace penumbra::raster
#endif  // HWY_ONCE
