// Every SIMD target against the scalar reference, kernel by kernel, on random planes,
// runs and shadow maps — including NaN/Inf depths, out-of-map lookups and PCF edges; and
// the bound of raster/receiver_bands.h on where a band's lookups can land.
#include "raster/span_kernels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include "raster/frame_trace.h"
#include "raster/receiver_bands.h"
#include "raster/shadow_map.h"
#include "tests/isa_params.h"

namespace penumbra::raster {
namespace {

constexpr int32_t kRow = 128;  // padded row: runs stay inside [0, 112)

struct Rows {
  std::vector<uint8_t> rgba;
  std::vector<float> depth;
  std::vector<uint32_t> id;
};

Rows randomRows(std::mt19937& rng) {
  Rows r;
  r.rgba.resize(4 * kRow);
  r.depth.resize(kRow);
  r.id.resize(kRow);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_real_distribution<float> z(0.0f, 1.0f);
  for (auto& b : r.rgba) b = static_cast<uint8_t>(byte(rng));
  for (int x = 0; x < kRow; ++x) {
    r.depth[x] = z(rng);
    r.id[x] = static_cast<uint32_t>(byte(rng) % 3);  // ids 0..2; the kernels look for 1
  }
  r.depth[5] = std::numeric_limits<float>::infinity();
  r.depth[17] = std::numeric_limits<float>::quiet_NaN();
  return r;
}

SpanPlanes randomPlanes(std::mt19937& rng) {
  std::uniform_real_distribution<float> f(-0.02f, 0.02f);
  std::uniform_int_distribution<uint32_t> u(0, 0xFFFFFFFFu);
  SpanPlanes p;
  p.depth = {0.5f + f(rng) * 10, f(rng), f(rng)};
  for (auto& a : p.rgb)
    a = {u(rng) % (255u << 16), u(rng) % 20000u - 10000u, u(rng) % 20000u - 10000u};
  p.ox = 3;
  p.oy = 2;
  return p;
}

class SpanKernelsOnTarget : public ::testing::TestWithParam<simd::Isa> {};

TEST_P(SpanKernelsOnTarget, DepthAndColourMatchScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(11);
  std::uniform_int_distribution<int32_t> pos(0, 111);
  for (int trial = 0; trial < 2000; ++trial) {
    Rows a = randomRows(rng);
    Rows b = a;
    const SpanPlanes p = randomPlanes(rng);
    int32_t xa = pos(rng), xb = pos(rng);
    if (xa > xb) std::swap(xa, xb);
    const int32_t y = trial % 40;
    if (trial % 2 == 0) {
      ASSERT_EQ(ref.depthLess(a.depth.data(), a.id.data(), xa, xb, y, p, 9),
                k.depthLess(b.depth.data(), b.id.data(), xa, xb, y, p, 9));
    } else {
      const uint32_t objectId = kObjectBase + uint32_t(trial);
      ASSERT_EQ(ref.colourLess(a.rgba.data(), a.depth.data(), a.id.data(), xa, xb, y, p, objectId),
                k.colourLess(b.rgba.data(), b.depth.data(), b.id.data(), xa, xb, y, p, objectId));
    }
    ASSERT_EQ(std::memcmp(a.depth.data(), b.depth.data(), 4 * kRow), 0) << trial;
    ASSERT_EQ(a.id, b.id) << trial;
    ASSERT_EQ(a.rgba, b.rgba) << trial;
  }
}

TEST_P(SpanKernelsOnTarget, DepthTriangleMatchesScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(15);
  // A quarter of the triangles are large (the exact-run path), the rest span at most 40
  // pixels (int32 edge tests): one vector per row (<= 40 px), two rows per vector
  // (<= 10 px) and 4x4 blocks (<= 5 px, on 16-lane targets). Centres range past every
  // border of the 64x64 buffer, so boxes get clipped at the map's edges.
  std::uniform_int_distribution<int32_t> coord(-20 * 256, 90 * 256), offset(-40 * 256, 40 * 256);
  std::uniform_real_distribution<float> z(0.0f, 1.0f);
  // Three spare rows and a vector of slack: the block paths may rewrite unchanged lanes
  // there (as ShadowMap allows).
  std::vector<float> a(67 * 64 + 16, 0.6f), b = a;
  std::vector<uint32_t> ida(64 * 64, 0), idb = ida;
  for (int trial = 0; trial < 4000; ++trial) {
    std::array<SnappedVertex, 3> v;
    const int32_t cx = coord(rng), cy = coord(rng);
    const int32_t shrink = std::array<int32_t, 4>{1, 2, 8, 16}[size_t(trial % 4)];
    for (auto& p : v) {
      p.x = trial % 4 == 0 ? coord(rng) : cx + offset(rng) / shrink;
      p.y = trial % 4 == 0 ? coord(rng) : cy + offset(rng) / shrink;
      p.z = z(rng);
    }
    // Some slivers and single-pixel triangles: two vertices close together.
    if (trial % 7 == 3) v[2] = {v[1].x + 1, v[1].y + (trial % 3) - 1, v[2].z, {}};
    // Horizontal and vertical edges (A = 0 or B = 0), and long slivers across the map.
    if (trial % 13 == 7) v[1].y = v[0].y;
    if (trial % 17 == 9) v[2].x = v[0].x;
    if (trial % 19 == 4) v[1] = {v[0].x + 90 * 256, v[0].y + 70 * 256 + trial % 300, v[1].z, {}};
    if (trial % 11 == 5) {
      v[1] = {v[0].x + 200, v[0].y + 17, v[1].z, {}};
      v[2] = {v[0].x + 60, v[0].y + 230, v[2].z, {}};
    }
    if (trial % 23 == 11) {
      // Guard-band sized: vertices up to 2^21 sub-pixels away (spec §3's range is 2^22), a
      // thin wedge through the buffer, so edge values reach 2^44 where the runs are cut.
      const int32_t far = (1 << 21) - offset(rng) * 8;
      v[0] = {cx - far, cy - far / (1 + trial % 5), v[0].z, {}};
      v[1] = {cx + far, cy + far / (1 + trial % 5) + offset(rng), v[1].z, {}};
      v[2] = {cx + far + offset(rng), cy + far / (1 + trial % 5) - 40 * 256, v[2].z, {}};
    }
    if (trial % 29 == 13) {
      // Tall and narrow (at most a few pixels wide, taller than isSmall's 64 pixels).
      v[1] = {v[0].x + 2 * 256 + trial % 200, v[0].y + 100 * 256, v[1].z, {}};
      v[2] = {v[0].x + trial % 300 - 100, v[0].y + 80 * 256 + trial % 500, v[2].z, {}};
    }
    SetupTriangle t;
    if (!setupTriangle(v, 64, 64, t)) continue;
    uint32_t* idA = trial % 3 == 2 ? ida.data() : nullptr;
    uint32_t* idB = trial % 3 == 2 ? idb.data() : nullptr;
    ASSERT_EQ(ref.depthTriangle(a.data(), idA, 64, t, uint32_t(trial)),
              k.depthTriangle(b.data(), idB, 64, t, uint32_t(trial)));
    ASSERT_EQ(std::memcmp(a.data(), b.data(), 4 * a.size()), 0) << trial;
    ASSERT_EQ(ida, idb) << trial;
  }
}

TEST_P(SpanKernelsOnTarget, InterpolateSMatchesScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(13);
  std::uniform_int_distribution<int32_t> pos(0, 111);
  for (int trial = 0; trial < 2000; ++trial) {
    Rows rows = randomRows(rng);
    std::vector<uint32_t> a(kRow, 0), b(kRow, 0);
    const SpanPlanes p = randomPlanes(rng);
    int32_t xa = pos(rng), xb = pos(rng);
    if (xa > xb) std::swap(xa, xb);
    ASSERT_EQ(ref.interpolateS(a.data(), rows.id.data(), xa, xb, trial % 40, p, 1),
              k.interpolateS(b.data(), rows.id.data(), xa, xb, trial % 40, p, 1));
    ASSERT_EQ(a, b) << trial;
  }
}

// The per-triangle form against its definition: interpolateS of the scalar reference on
// each row's run, the row bounds widened only where a pixel matched.
TEST_P(SpanKernelsOnTarget, InterpolateRunsMatchesPerRowScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(14);
  std::uniform_int_distribution<int32_t> pos(0, 111);
  std::uniform_int_distribution<uint32_t> any(0, 0xFFFFFFFFu);
  constexpr int32_t kRows = 24;
  for (int trial = 0; trial < 1500; ++trial) {
    std::vector<uint32_t> id(size_t(kRow) * kRows);
    for (auto& v : id) v = any(rng) % 3;  // the kernels look for 1 (or 2, below)
    std::vector<uint32_t> expected(id.size());
    for (auto& v : expected) v = any(rng);  // lanes not matched must keep their value
    std::vector<uint32_t> got = expected;
    std::vector<int32_t> beginA(kRows), endA(kRows);
    for (int32_t y = 0; y < kRows; ++y) {
      beginA[y] = pos(rng);
      endA[y] = pos(rng);
    }
    std::vector<int32_t> beginB = beginA, endB = endA;
    const int32_t y0 = trial % 5, y1 = kRows - trial % 3;
    std::vector<std::pair<int32_t, int32_t>> runs(size_t(y1 - y0));
    for (auto& r : runs) {
      r = {pos(rng), pos(rng)};
      if (trial % 4 != 0 && r.first > r.second) std::swap(r.first, r.second);  // else empty
    }
    SpanPlanes p = randomPlanes(rng);
    p.ox = trial % 7;
    p.oy = y0 + trial % 2;
    const uint32_t want = 1 + uint32_t(trial % 2);
    uint32_t matched = 0;
    for (int32_t y = y0; y < y1; ++y) {
      const auto [xa, xb] = runs[size_t(y - y0)];
      if (xa >= xb) continue;
      const size_t row = size_t(kRow) * size_t(y);
      const uint32_t n = ref.interpolateS(&expected[row], &id[row], xa, xb, y, p, want);
      if (n == 0) continue;
      matched += n;
      beginA[y] = std::min(beginA[y], xa);
      endA[y] = std::max(endA[y], xb);
    }
    ASSERT_EQ(k.interpolateRuns(got.data(), id.data(), kRow, y0, y1, runs.data(), p, want,
                                beginB.data(), endB.data()),
              matched)
        << trial;
    ASSERT_EQ(got, expected) << trial;
    ASSERT_EQ(beginB, beginA) << trial;
    ASSERT_EQ(endB, endA) << trial;
  }
}

// The 8.8 form: the target against the scalar reference on the same runs, into three planes
// whose unmatched pixels must keep their values; matched pixels in [0, 255 * 256].
TEST_P(SpanKernelsOnTarget, InterpolateRunsFineMatchesScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(15);
  std::uniform_int_distribution<int32_t> pos(0, 111);
  std::uniform_int_distribution<uint32_t> any(0, 0xFFFFFFFFu);
  constexpr int32_t kRows = 24;
  const size_t plane = size_t(kRow) * kRows;
  for (int trial = 0; trial < 1500; ++trial) {
    std::vector<uint32_t> id(plane);
    for (auto& v : id) v = any(rng) % 3;
    std::vector<uint16_t> expected(3 * plane);
    for (auto& v : expected) v = static_cast<uint16_t>(any(rng));
    std::vector<uint16_t> got = expected;
    std::vector<int32_t> beginA(kRows), endA(kRows);
    for (int32_t y = 0; y < kRows; ++y) {
      beginA[y] = pos(rng);
      endA[y] = pos(rng);
    }
    std::vector<int32_t> beginB = beginA, endB = endA;
    const int32_t y0 = trial % 5, y1 = kRows - trial % 3;
    std::vector<std::pair<int32_t, int32_t>> runs(size_t(y1 - y0));
    for (auto& r : runs) {
      r = {pos(rng), pos(rng)};
      if (trial % 4 != 0 && r.first > r.second) std::swap(r.first, r.second);
    }
    SpanPlanes p = randomPlanes(rng);
    p.ox = trial % 7;
    p.oy = y0 + trial % 2;
    const uint32_t want = 1 + uint32_t(trial % 2);
    const uint32_t a = ref.interpolateRunsFine(expected.data(), plane, id.data(), kRow, y0, y1,
                                               runs.data(), p, want, beginA.data(), endA.data());
    const uint32_t b = k.interpolateRunsFine(got.data(), plane, id.data(), kRow, y0, y1,
                                             runs.data(), p, want, beginB.data(), endB.data());
    ASSERT_EQ(a, b) << trial;
    ASSERT_EQ(got, expected) << trial;
    ASSERT_EQ(beginB, beginA) << trial;
    ASSERT_EQ(endB, endA) << trial;
  }
}

// One accumulation kernel of `ref` and of the target on copies of the same inputs: the same
// sums, and the scratch (packed S, or the three 8.8 planes) left clean by both.
template <class Scratch>
using AccumulateKernelOf = void (*)(const float*, Scratch*, uint16_t*, size_t, size_t, int32_t,
                                    int32_t, const int32_t*, const int32_t*, const ShadowLookup&);

template <class Scratch>
void expectSameSums(AccumulateKernelOf<Scratch> refKernel, AccumulateKernelOf<Scratch> kernel,
                    const std::vector<float>& depth, const std::vector<Scratch>& s,
                    std::vector<uint16_t> acc, size_t plane, int32_t rows,
                    const std::vector<int32_t>& xa, const std::vector<int32_t>& xb,
                    const ShadowLookup& lookup, int trial) {
  std::vector<Scratch> sA = s, sB = s;
  std::vector<uint16_t> accB = acc;
  refKernel(depth.data(), sA.data(), acc.data(), plane, kRow, 0, rows, xa.data(), xb.data(),
            lookup);
  kernel(depth.data(), sB.data(), accB.data(), plane, kRow, 0, rows, xa.data(), xb.data(), lookup);
  ASSERT_EQ(acc, accB) << "trial " << trial;
  ASSERT_EQ(sA, sB) << "trial " << trial;
  for (Scratch v : sA) ASSERT_EQ(v, 0u) << "scratch must be left clean";
}

// The 8.8 planes of a packed scratch: each channel's whole level with a pseudo-random
// fraction, 0 where the channel is 0 (so unmarked pixels stay unmarked).
std::vector<uint16_t> finePlanes(const std::vector<uint32_t>& packed) {
  std::vector<uint16_t> planes(3 * packed.size(), 0);
  for (size_t i = 0; i < packed.size(); ++i) {
    const uint32_t hash = packed[i] * 2654435761u;
    for (size_t c = 0; c < 3; ++c) {
      const uint32_t whole = (packed[i] >> (8 * c)) & 0xFFu;
      if (whole == 0) continue;
      const uint32_t fraction = (hash >> (8 * c)) & 0xFFu;
      planes[c * packed.size() + i] =
          static_cast<uint16_t>(std::min<uint32_t>(whole * 256 + fraction, core::kMaxFineLevel));
    }
  }
  return planes;
}

// Both accumulation modes (spec §8) from the sums `start`; the fixed-point ones also from
// sums near 65535, where they saturate.
void expectSameAccumulation(const SpanKernels& ref, const SpanKernels& k,
                            const std::vector<float>& depth, const std::vector<uint32_t>& s,
                            const std::vector<uint16_t>& start, size_t plane, int32_t rows,
                            const std::vector<int32_t>& xa, const std::vector<int32_t>& xb,
                            const ShadowLookup& lookup, int trial) {
  expectSameSums(ref.accumulateRows, k.accumulateRows, depth, s, start, plane, rows, xa, xb, lookup,
                 trial);
  const std::vector<uint16_t> fine = finePlanes(s);
  expectSameSums(ref.accumulateRowsFine, k.accumulateRowsFine, depth, fine, start, plane, rows, xa,
                 xb, lookup, trial);
  std::vector<uint16_t> high = start;
  for (uint16_t& v : high) v = static_cast<uint16_t>(65535 - v / 3);
  expectSameSums(ref.accumulateRowsFine, k.accumulateRowsFine, depth, fine, high, plane, rows, xa,
                 xb, lookup, trial);
}

TEST_P(SpanKernelsOnTarget, AccumulateRowsMatchesScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(12);
  std::uniform_int_distribution<int32_t> pos(0, 111);
  std::uniform_int_distribution<uint32_t> bits(0, 0xFFFFFFu);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  const int32_t size = 32, rows = 6;
  const size_t plane = size_t{kRow} * rows;
  ShadowMap map;
  map.reset(size);
  for (int32_t j = 0; j < size; ++j) {
    for (int32_t i = 0; i < size; ++i) {
      map.origin()[j * map.stride() + i] = 0.3f + 0.4f * (f(rng) + 1.0f) / 2.0f;
    }
  }
  map.origin()[7] = std::numeric_limits<float>::infinity();
  for (int trial = 0; trial < 1500; ++trial) {
    std::vector<float> depth(plane);
    std::vector<uint32_t> sA(plane, 0);
    std::vector<uint16_t> accA(3 * plane);
    for (float& v : depth) v = 0.5f + 0.5f * f(rng);
    for (auto& v : accA) v = static_cast<uint16_t>(bits(rng) % 30000);
    depth[9] = std::numeric_limits<float>::quiet_NaN();
    depth[kRow + 3] = std::numeric_limits<float>::infinity();
    std::vector<int32_t> xa(rows), xb(rows);
    for (int r = 0; r < rows; ++r) {
      xa[r] = pos(rng);
      xb[r] = pos(rng);
      if (xa[r] > xb[r]) std::swap(xa[r], xb[r]);
      for (int32_t x = xa[r]; x < xb[r]; ++x) {
        // Mostly marked pixels, some unmarked (S = 0), some with channels zero.
        if (bits(rng) % 5 != 0) {
          sA[size_t(r) * kRow + size_t(x)] = bits(rng) & (bits(rng) % 3 ? 0xFFFFFFu : 0x00FF00u);
        }
      }
    }
    ShadowLookup lookup{};
    // A projective map that sends the rows across (and beyond) the shadow map.
    for (float& v : lookup.p) v = f(rng);
    lookup.p[0] = 0.4f + 0.1f * f(rng);
    lookup.p[3] = 16.0f * f(rng);
    lookup.p[5] = 0.5f;
    lookup.p[7] = 12.0f + 8.0f * f(rng);
    lookup.p[12] = 0.001f * f(rng);
    lookup.p[13] = 0.001f * f(rng);
    lookup.p[15] = 1.0f + 0.2f * f(rng);
    lookup.map = map.origin();
    lookup.size = size;
    lookup.stride = map.stride();
    lookup.bias = 0.01f * (f(rng) + 1.0f);
    lookup.pcf2x2 = trial % 2 == 1;
    expectSameAccumulation(ref, k, depth, sA, accA, plane, rows, xa, xb, lookup, trial);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// A new map for the block and area tests: `triangles` small triangles drawn by the
// reference's depthTriangle in one part of `map` (blocks marked as the renderer marks
// them), the rest +inf. Returns the rectangle [x0, x1) x [y0, y1) of their bounding boxes.
std::array<int32_t, 4> drawPatchyMap(ShadowMap& map, int triangles, std::mt19937& rng) {
  const int32_t size = map.size();
  std::uniform_int_distribution<int32_t> corner(0, 40 * 256), extent(0, 12 * 256);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  map.clear(0, 0, size, size);
  std::array<int32_t, 4> rect{size, size, 0, 0};
  const int32_t cx = corner(rng), cy = corner(rng);
  for (int n = 0; n < triangles; ++n) {
    std::array<SnappedVertex, 3> v;
    for (auto& p : v) {
      p.x = cx + extent(rng);
      p.y = cy + extent(rng);
      p.z = 0.3f + 0.2f * (f(rng) + 1.0f);
    }
    SetupTriangle t;
    if (!setupTriangle(v, uint32_t(size), uint32_t(size), t)) continue;
    scalarSpanKernels().depthTriangle(map.origin(), nullptr, size_t(map.stride()), t, 0);
    map.markWritten(t.minX, t.minY, t.maxX, t.maxY);
    rect = {std::min(rect[0], t.minX), std::min(rect[1], t.minY), std::max(rect[2], t.maxX),
            std::max(rect[3], t.maxY)};
  }
  return rect;
}

// Random rows of a sweep for the block and area tests: depths in [0.1, 1], marked pixels
// with every channel odd, and a lookup sending pixels (0..111, 0..5) to texels around
// (-2..50): across the drawn part of `map` and its border.
void randomSweep(std::mt19937& rng, const ShadowMap& map, int32_t rows, std::vector<float>& depth,
                 std::vector<uint32_t>& s, std::vector<uint16_t>& acc, std::vector<int32_t>& xa,
                 std::vector<int32_t>& xb, ShadowLookup& lookup) {
  std::uniform_int_distribution<int32_t> pos(0, 111);
  std::uniform_int_distribution<uint32_t> bits(0, 0xFFFFFFu);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  const size_t plane = size_t{kRow} * size_t(rows);
  depth.assign(plane, 0.0f);
  s.assign(plane, 0);
  acc.assign(3 * plane, 0);
  for (float& v : depth) v = 0.55f + 0.45f * f(rng);
  for (auto& v : acc) v = static_cast<uint16_t>(bits(rng) % 30000);
  xa.assign(size_t(rows), 0);
  xb.assign(size_t(rows), 0);
  for (int32_t r = 0; r < rows; ++r) {
    xa[size_t(r)] = pos(rng);
    xb[size_t(r)] = pos(rng);
    if (xa[size_t(r)] > xb[size_t(r)]) std::swap(xa[size_t(r)], xb[size_t(r)]);
    for (int32_t x = xa[size_t(r)]; x < xb[size_t(r)]; ++x) {
      if (bits(rng) % 5 != 0) s[size_t(r) * kRow + size_t(x)] = bits(rng) | 1u;
    }
  }
  lookup = ShadowLookup{};
  lookup.p[0] = 0.45f + 0.02f * f(rng);
  lookup.p[1] = 0.05f * f(rng);
  lookup.p[3] = -2.0f + 2.0f * f(rng);
  lookup.p[4] = 0.05f * f(rng);
  lookup.p[5] = 1.0f + 0.5f * f(rng);
  lookup.p[7] = 48.0f * (f(rng) + 1.0f) / 2.0f;
  lookup.p[10] = 1.0f;
  lookup.p[15] = 1.0f;
  lookup.map = map.origin();
  lookup.size = map.size();
  lookup.stride = map.stride();
  lookup.bias = 0.005f;
  lookup.blocks = map.blocks();
  lookup.blocksPerRow = map.blocksPerRow();
}

// 1500 sweeps over maps redrawn every 50 by drawPatchyMap: without `area`, 2x2 PCF and binary
// lookups with the block table; with it, area-light lookups (their coverage counts summed as
// the renderer sums them) with depths in front of, among and behind the occluder's, boxes
// from under a texel to past the 32-texel cap and wholly off the map, NaN and infinite depths.
void expectSameOnPatchyMaps(const SpanKernels& k, uint32_t seed, bool area) {
  const SpanKernels& ref = scalarSpanKernels();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  const int32_t rows = 6;
  const size_t plane = size_t{kRow} * rows;
  ShadowMap map;
  map.reset(48);
  std::vector<float> depth;
  std::vector<uint32_t> sA;
  std::vector<uint16_t> accA;
  std::vector<int32_t> xa, xb;
  ShadowLookup lookup;
  for (int trial = 0; trial < 1500; ++trial) {
    if (trial % 50 == 0) {  // with `area`, trial 0 draws an empty map
      const std::array<int32_t, 4> rect = drawPatchyMap(map, area ? trial % 9 : 1 + trial % 7, rng);
      map.sumBlocks();
      map.sumCoverage(rect[0], rect[1], rect[2], rect[3]);
    }
    randomSweep(rng, map, rows, depth, sA, accA, xa, xb, lookup);
    lookup.pcf2x2 = area || trial % 3 != 0;
    if (area) {
      for (float& d : depth) d = 0.1f + 0.9f * (f(rng) + 1.0f) / 2.0f;
      depth[9] = std::numeric_limits<float>::quiet_NaN();
      depth[kRow + 3] = std::numeric_limits<float>::infinity();
      if (trial % 11 == 0) lookup.p[3] += 200.0f;
      setAreaPenumbra(lookup, map,
                      trial % 4 == 0 ? 400.0f * (f(rng) + 1.0f) : 40.0f * (f(rng) + 1.0f));
    }
    expectSameAccumulation(ref, k, depth, sA, accA, plane, rows, xa, xb, lookup, trial);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// The block table lets kernels skip lanes whose texels are all +inf. Maps drawn by
// depthTriangle over part of the map (blocks marked as the renderer marks them), lookups
// sweeping across drawn, undrawn and border texels: the same sums as the reference, which
// ignores the table.
TEST_P(SpanKernelsOnTarget, AccumulateRowsWithBlocksMatchesScalar) {
  expectSameOnPatchyMaps(spanKernelsFor(GetParam()), 16, false);
}

// Area-light penumbrae (spec §7): the same sums as the reference.
TEST_P(SpanKernelsOnTarget, AccumulateRowsWithAreaPenumbraeMatchesScalar) {
  expectSameOnPatchyMaps(spanKernelsFor(GetParam()), 19, true);
}

// An area-penumbra lookup of scale `k` into `map` (after its sumCoverage) along one row:
// pixel (x, 0) of depth z looks up texel (x - 32 + 0.5, row + 0.5) at light depth d = z.
ShadowLookup rowLookup(const ShadowMap& map, float k, float row) {
  ShadowLookup lookup{};
  lookup.p[0] = 1.0f;
  lookup.p[3] = -32.0f;
  lookup.p[7] = row;
  lookup.p[10] = 1.0f;
  lookup.p[15] = 1.0f;
  lookup.map = map.origin();
  lookup.size = map.size();
  lookup.stride = map.stride();
  lookup.bias = 0.001f;
  lookup.pcf2x2 = true;
  setAreaPenumbra(lookup, map, k);
  return lookup;
}

// What the area lookup computes (spec §7), on the reference: an occluder filling columns
// [0, 24) of a 48-texel map at depth 0.3, receivers at depth 0.7 with a 4-texel half-width
// box, along a row of texel centres. Its weight falls linearly from 65536 four texels inside
// the edge to 0 four texels past it, through a half at the edge; a receiver among the
// occluder's depths keeps the 2x2 PCF's hard edge.
TEST(AreaPenumbra, BoxCoverageRampsAcrossAnEdge) {
  const int32_t size = 48;
  ShadowMap map;
  map.reset(size);
  for (int32_t j = 0; j < size; ++j) {
    for (int32_t i = 0; i < 24; ++i) map.origin()[j * map.stride() + i] = 0.3f;
  }
  map.sumCoverage(0, 0, 24, size);
  EXPECT_EQ(map.farthest(), 0.3f);
  const ShadowLookup lookup = rowLookup(map, 10.0f, 20.0f);  // 10 (0.7 - 0.3) = 4 texels
  const size_t plane = kRow;
  auto weights = [&](float d) {
    std::vector<float> depth(plane, d);
    // S = 255 in red only: the sum gains round(255 W / 65536)-ish per pixel (spec §8, u8).
    std::vector<uint32_t> s(plane, 0xFFu);
    std::vector<uint16_t> acc(3 * plane, 0);
    const int32_t xa = 40, xb = 72;  // u from 8.5 to 39.5
    scalarSpanKernels().accumulateRows(depth.data(), s.data(), acc.data(), plane, kRow, 0, 1, &xa,
                                       &xb, lookup);
    return acc;
  };
  const std::vector<uint16_t> soft = weights(0.7f);
  EXPECT_EQ(soft[40 + 11], 255);                 // u = 19.5: the box [15.5, 23.5] is all occluder
  EXPECT_EQ(soft[40 + 20], 0);                   // u = 28.5: [24.5, 32.5], none
  EXPECT_NEAR(soft[40 + 15], 255 * 4.5 / 8, 1);  // u = 23.5: 4.5 of the box's 8 texels
  EXPECT_NEAR(soft[40 + 17], 255 * 2.5 / 8, 1);  // u = 25.5
  for (int x = 41; x < 72; ++x) EXPECT_LE(soft[size_t(x)], soft[size_t(x) - 1]) << x;
  // Depth 0.25 is in front of the occluder: the 2x2 PCF, which sees nothing in front of it.
  const std::vector<uint16_t> front = weights(0.25f);
  for (int x = 40; x < 72; ++x) EXPECT_EQ(front[size_t(x)], 0) << x;
}

// The per-pixel blocker search (spec §7): two occluders across the light's view, one near it
// (depth 0.2, rows [0, 32)) and one far (0.6, rows [32, 64)), both ending at column 24.
// Behind both (depth 0.8, K = 10) each edge ramps over its own blocker's penumbra,
// 2 K (0.8 - 0.2) = 12 texels near and 2 K (0.8 - 0.6) = 4 far, centred on the edge; one
// blocker depth per pass would give both edges one width.
TEST(AreaPenumbra, EachEdgeRampsOverItsOwnBlockersPenumbra) {
  const int32_t size = 64;
  ShadowMap map;
  map.reset(size);
  for (int32_t j = 0; j < size; ++j) {
    for (int32_t i = 0; i < 24; ++i) map.origin()[j * map.stride() + i] = j < 32 ? 0.2f : 0.6f;
  }
  map.sumCoverage(0, 0, 24, size);
  EXPECT_EQ(map.nearest(), 0.2f);
  auto rampAt = [&](float row) {
    const ShadowLookup lookup = rowLookup(map, 10.0f, row);
    const size_t plane = kRow;
    std::vector<float> depth(plane, 0.8f);
    std::vector<uint32_t> s(plane, 0xFFu);
    std::vector<uint16_t> acc(3 * plane, 0);
    const int32_t xa = 40, xb = 72;  // u from 8.5 to 39.5
    scalarSpanKernels().accumulateRows(depth.data(), s.data(), acc.data(), plane, kRow, 0, 1, &xa,
                                       &xb, lookup);
    int partial = 0;
    for (int x = xa; x < xb; ++x) partial += acc[size_t(x)] > 0 && acc[size_t(x)] < 255;
    // Halfway at the edge: u = 23.5 and 24.5 straddle it.
    EXPECT_NEAR(acc[40 + 15] + acc[40 + 16], 255, 40) << row;
    return partial;
  };
  const int nearRamp = rampAt(16.0f), farRamp = rampAt(48.0f);
  EXPECT_GE(nearRamp, 11);
  EXPECT_LE(nearRamp, 13);
  EXPECT_GE(farRamp, 3);
  EXPECT_LE(farRamp, 5);
}

using FinishKernel = decltype(SpanKernels::shadeAccumulatedLinear);

// One finishing kernel of `ref` and of the target on `count` random sum planes below
// `limit`: the same bytes, and the run's sums zeroed by both. `table` (padded by 3 bytes)
// is passed to the linear kernels only.
template <class Kernel>
void expectSameFinish(Kernel refKernel, Kernel kernel, std::mt19937& rng, int count, uint32_t limit,
                      int trial, const std::vector<uint8_t>& table = {}) {
  std::uniform_int_distribution<int32_t> pos(0, 111);
  std::uniform_int_distribution<uint32_t> bits(0, 0xFFFFFFFFu);
  const size_t plane = kRow;
  std::vector<std::vector<uint16_t>> accA(size_t(count), std::vector<uint16_t>(3 * plane));
  for (auto& a : accA) {
    for (auto& v : a) v = static_cast<uint16_t>(bits(rng) % limit);
  }
  auto accB = accA;
  std::vector<uint8_t> baseA(4 * kRow);
  for (auto& v : baseA) v = static_cast<uint8_t>(bits(rng));
  std::vector<uint8_t> baseB = baseA;
  std::vector<uint16_t*> pa, pb;
  for (int i = 0; i < count; ++i) {
    pa.push_back(accA[size_t(i)].data());
    pb.push_back(accB[size_t(i)].data());
  }
  int32_t xa = pos(rng), xb = pos(rng);
  if (xa > xb) std::swap(xa, xb);
  if constexpr (std::is_same_v<Kernel, FinishKernel>) {
    refKernel(baseA.data(), baseA.data(), pa.data(), count, plane, xa, xb, table.data());
    kernel(baseB.data(), baseB.data(), pb.data(), count, plane, xa, xb, table.data());
  } else {
    refKernel(baseA.data(), baseA.data(), pa.data(), count, plane, xa, xb);
    kernel(baseB.data(), baseB.data(), pb.data(), count, plane, xa, xb);
  }
  ASSERT_EQ(baseA, baseB) << "trial " << trial;
  ASSERT_EQ(accA, accB) << "trial " << trial;
}

TEST_P(SpanKernelsOnTarget, SubtractAccumulatedMatchesScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(14);
  for (int trial = 0; trial < 1000; ++trial) {
    const int count = 1 + trial % 4;
    expectSameFinish(ref.subtractAccumulated, k.subtractAccumulated, rng, count,
                     trial % 2 ? 300u : 20u, trial);
    // Fixed-point sums: around one level (256) up to saturated planes.
    expectSameFinish(ref.subtractAccumulatedFixed8_8, k.subtractAccumulatedFixed8_8, rng, count,
                     trial % 2 ? 65536u : 2000u, trial);
    if (HasFatalFailure()) return;
  }
}

// Linear accumulation's shade-table lookup: a random table (every entry distinct in its
// neighbourhood, so an index off by one shows), sums from none to saturated.
TEST_P(SpanKernelsOnTarget, ShadeAccumulatedLinearMatchesScalar) {
  const SpanKernels& ref = scalarSpanKernels();
  const SpanKernels& k = spanKernelsFor(GetParam());
  std::mt19937 rng(17);
  std::vector<uint8_t> table(kShadeCodes * kShadeSteps + 3, 0);
  for (size_t i = 0; i < kShadeCodes * kShadeSteps; ++i) table[i] = static_cast<uint8_t>(i * 131);
  for (int trial = 0; trial < 1000; ++trial) {
    expectSameFinish(ref.shadeAccumulatedLinear, k.shadeAccumulatedLinear, rng, 1 + trial % 4,
                     trial % 3 == 0 ? 65536u : 30000u, trial, table);
    if (HasFatalFailure()) return;
  }
  // The scalar reference is the spec's formula: base code 200, sums 1000 + 300 -> q = 10.
  std::vector<uint16_t> sum(3 * kRow, 0), second(3 * kRow, 0);
  sum[5] = 1000;
  second[5] = 300;
  std::vector<uint8_t> base(4 * kRow, 200), out(4 * kRow, 0);
  uint16_t* planes[2] = {sum.data(), second.data()};
  ref.shadeAccumulatedLinear(out.data(), base.data(), planes, 2, kRow, 5, 6, table.data());
  EXPECT_EQ(out[20], table[200 * kShadeSteps + 10]);
  EXPECT_EQ(out[21], table[200 * kShadeSteps]);
  EXPECT_EQ(out[23], 200);
}

INSTANTIATE_TEST_SUITE_P(AllTargets, SpanKernelsOnTarget,
                         ::testing::ValuesIn(simd::supportedIsas()),
                         penumbra::testing::isaTestName);

// Receiver bands (raster/receiver_bands.h): a band reported unwritten must hold no pixel,
// at any depth in its range, whose spec §7 lookup starts a footprint in a marked block.

// The footprint start (i, j) of spec §7 as the scalar reference computes it; false for a
// lookup that is not valid (W = 0 without reading the map).
bool footprintStart(const ShadowLookup& s, float sx, float sy, float z, int32_t& i, int32_t& j) {
  const float* p = s.p;
  const float q0 = ((p[0] * sx + p[1] * sy) + p[2] * z) + p[3];
  const float q1 = ((p[4] * sx + p[5] * sy) + p[6] * z) + p[7];
  const float q3 = ((p[12] * sx + p[13] * sy) + p[14] * z) + p[15];
  if (!(q3 > 0.0f)) return false;
  const float u = q0 / q3, v = q1 / q3, size = static_cast<float>(s.size);
  if (!s.pcf2x2) {
    if (!(u >= 0.0f && u < size && v >= 0.0f && v < size)) return false;
    i = static_cast<int32_t>(u);
    j = static_cast<int32_t>(v);
    return true;
  }
  const float up = u - 0.5f, vp = v - 0.5f;
  if (!(up > -1.0f && up < size && vp > -1.0f && vp < size)) return false;
  i = static_cast<int32_t>(std::floor(up));
  j = static_cast<int32_t>(std::floor(vp));
  return true;
}

// A band of up to 13 x 7 pixels at (x0, y0), its depths spanning up to 2 `depthSpread`
// within [0, 1].
ReceiverBand randomBand(std::mt19937& rng, int32_t x0, int32_t y0, float depthSpread) {
  std::uniform_int_distribution<int32_t> extent(0, 12);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  ReceiverBand band;
  band.x0 = x0;
  band.y0 = y0;
  band.x1 = band.x0 + extent(rng);
  band.y1 = band.y0 + extent(rng) / 2;
  band.zMin = 0.5f + 0.5f * f(rng);
  band.zMax = std::min(1.0f, band.zMin + depthSpread * (f(rng) + 1.0f));
  band.matched = 1;
  return band;
}

// A texel of the map within `spread` texels (each axis) of where the band's middle looks
// at its nearest depth, or anywhere when it looks at none.
std::pair<int32_t, int32_t> texelNear(const ShadowLookup& lookup, const ReceiverBand& band,
                                      std::mt19937& rng, int32_t spread) {
  std::uniform_int_distribution<int32_t> any(0, lookup.size - 1), near(-spread, spread);
  int32_t i, j;
  if (!footprintStart(lookup, static_cast<float>(band.x0 + band.x1) / 2 + 0.5f,
                      static_cast<float>(band.y0 + band.y1) / 2 + 0.5f, band.zMin, i, j)) {
    return {any(rng), any(rng)};
  }
  return {std::clamp(i + near(rng), 0, lookup.size - 1),
          std::clamp(j + near(rng), 0, lookup.size - 1)};
}

// Random projective lookups over small bands, each map with one marked block: whenever a
// band is reported unwritten, every pixel of its box at its extreme depths and at depths in
// between (the lookup is not monotone in z as a whole, only each q_r is) misses that block.
TEST(ReceiverBands, UnwrittenBandsNeverReachAMarkedBlock) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  std::uniform_int_distribution<int32_t> pos(0, 600);
  const int32_t size = 64;
  ShadowMap map;
  map.reset(size);
  int unwritten = 0, drawn = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    ShadowLookup lookup{};
    for (float& v : lookup.p) v = f(rng);
    // Window pixels to texels at about a tenth of a texel per pixel, a perspective divide
    // that varies across the band and with depth.
    lookup.p[0] = 0.1f + 0.02f * f(rng);
    lookup.p[1] = 0.02f * f(rng);
    lookup.p[4] = 0.02f * f(rng);
    lookup.p[3] = 32.0f * f(rng);
    lookup.p[5] = 0.1f + 0.02f * f(rng);
    lookup.p[7] = 32.0f * f(rng);
    lookup.p[12] = 0.0005f * f(rng);
    lookup.p[13] = 0.0005f * f(rng);
    lookup.p[14] = 0.3f * f(rng);
    lookup.p[15] = 1.0f + 0.2f * f(rng);
    lookup.size = size;
    lookup.pcf2x2 = trial % 2 == 1;
    // The marked texel within 4 texels of where the band's middle looks, so that bands
    // reach it, miss it narrowly, or are far from it.
    const ReceiverBand band = randomBand(rng, pos(rng), pos(rng), 0.01f);
    const auto [tx, ty] = texelNear(lookup, band, rng, 4);
    map.clear(0, 0, size, size);
    map.markWritten(tx, ty, tx + 1, ty + 1);
    map.sumBlocks();
    if (!LightFootprint(lookup, map).unwritten(band)) {
      ++drawn;
      continue;
    }
    ++unwritten;
    for (int32_t y = band.y0; y <= band.y1; ++y) {
      for (int32_t x = band.x0; x <= band.x1; ++x) {
        for (int step = 0; step <= 8; ++step) {
          const float z = step == 8
                              ? band.zMax
                              : band.zMin + (band.zMax - band.zMin) * static_cast<float>(step) / 8;
          int32_t i, j;
          if (!footprintStart(lookup, static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, z,
                              i, j)) {
            continue;
          }
          ASSERT_FALSE(map.blocks()[size_t((j + 8) >> 3) * size_t(map.blocksPerRow()) +
                                    size_t((i + 8) >> 3)] != 0)
              << "trial " << trial << " pixel " << x << "," << y << " z " << z;
        }
      }
    }
  }
  // Both answers occur, so the check above is not vacuous.
  EXPECT_GT(unwritten, 100);
  EXPECT_GT(drawn, 100);
}

// Area-penumbra passes (spec §7): a band LightFootprint calls unwritten, with the box
// half-widths its light depths allow, gets W = 0 at every pixel and depth: one occluder
// texel written at depth 0.2 near where the band looks, the scalar reference's sums over the
// band at 9 depths stay 0. Both answers occur.
TEST(ReceiverBands, UnwrittenAreaPenumbraBandsAddNothing) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> f(-1.0f, 1.0f);
  std::uniform_int_distribution<int32_t> pos(0, 100);
  const int32_t size = 64;
  ShadowMap map;
  map.reset(size);
  int unwritten = 0, drawn = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    ShadowLookup lookup{};
    lookup.p[0] = 0.3f + 0.05f * f(rng);
    lookup.p[1] = 0.02f * f(rng);
    lookup.p[3] = 32.0f * f(rng);
    lookup.p[4] = 0.02f * f(rng);
    lookup.p[5] = 0.3f + 0.05f * f(rng);
    lookup.p[7] = 32.0f * f(rng);
    lookup.p[10] = 0.5f + 0.1f * f(rng);  // light depth from the pixel's
    lookup.p[11] = 0.3f + 0.1f * f(rng);
    lookup.p[12] = 0.0005f * f(rng);
    lookup.p[15] = 1.0f + 0.2f * f(rng);
    lookup.size = size;
    lookup.stride = map.stride();
    lookup.map = map.origin();
    lookup.bias = 0.001f;
    lookup.pcf2x2 = true;
    const ReceiverBand band = randomBand(rng, pos(rng), pos(rng) % 20, 0.05f);
    const auto [tx, ty] = texelNear(lookup, band, rng, 40);
    map.clear(0, 0, size, size);
    map.origin()[ty * map.stride() + tx] = 0.2f;
    map.markWritten(tx, ty, tx + 1, ty + 1);
    map.sumBlocks();
    map.sumCoverage(tx, ty, tx + 1, ty + 1);
    setAreaPenumbra(lookup, map, 30.0f * (f(rng) + 1.0f));
    if (!LightFootprint(lookup, map).unwritten(band)) {
      ++drawn;
      continue;
    }
    ++unwritten;
    const int32_t stride = band.x1 + 1, rows = band.y1 + 1;
    const size_t plane = size_t(stride) * size_t(rows);
    std::vector<int32_t> xa(size_t(rows), band.x0), xb(size_t(rows), band.x1 + 1);
    for (int step = 0; step <= 8; ++step) {
      const float z = band.zMin + (band.zMax - band.zMin) * static_cast<float>(step) / 8;
      std::vector<float> depth(plane, z);
      std::vector<uint32_t> sPlane(plane, 0xFFFFFFu);
      std::vector<uint16_t> acc(3 * plane, 0);
      scalarSpanKernels().accumulateRows(depth.data(), sPlane.data(), acc.data(), plane,
                                         size_t(stride), band.y0, rows, &xa[size_t(band.y0)],
                                         &xb[size_t(band.y0)], lookup);
      ASSERT_TRUE(std::all_of(acc.begin(), acc.end(), [](uint16_t v) { return v == 0; }))
          << "trial " << trial << " z " << z;
    }
  }
  EXPECT_GT(unwritten, 100);
  EXPECT_GT(drawn, 100);
}

// What cannot be bounded is drawn: q3 <= 0 somewhere in the band, or an infinite entry.
TEST(ReceiverBands, UnboundedLookupsAreDrawn) {
  ShadowMap map;
  map.reset(16);
  map.sumBlocks();
  ShadowLookup lookup{};
  lookup.size = 16;
  lookup.p[0] = lookup.p[5] = 1.0f;
  lookup.p[15] = 1.0f;
  lookup.p[12] = -0.01f;  // q3 = 1 - 0.01 sx: negative right of x = 100
  ReceiverBand band{90, 0, 120, 3, 0.5f, 0.6f, 10};
  EXPECT_FALSE(LightFootprint(lookup, map).unwritten(band));
  band.x1 = 95;  // q3 > 0 everywhere: nothing is marked, so nothing can be occluded
  EXPECT_TRUE(LightFootprint(lookup, map).unwritten(band));
  lookup.p[2] = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(LightFootprint(lookup, map).unwritten(band));
}

TEST(ReceiverBands, BandsSummariseTheMatchingPixels) {
  const size_t stride = 16;
  std::vector<float> depth(stride * 20, 0.25f);
  std::vector<uint32_t> id(stride * 20, 3);
  id[stride * 2 + 5] = 4;  // another triangle won this pixel
  depth[stride * 9 + 6] = 0.75f;
  std::vector<std::pair<int32_t, int32_t>> runs(12, {4, 8});
  runs[11] = {0, 0};
  std::vector<ReceiverBand> bands;
  appendReceiverBands(1, 13, runs.data(), depth.data(), id.data(), stride, 3, bands);
  ASSERT_EQ(bands.size(), 2u);  // rows 1-8 and 9-12
  EXPECT_EQ(bands[0].matched, 8u * 4 - 1);
  EXPECT_EQ(bands[0].x0, 4);
  EXPECT_EQ(bands[0].x1, 7);
  EXPECT_EQ(bands[0].y0, 1);
  EXPECT_EQ(bands[0].y1, 8);
  EXPECT_EQ(bands[1].matched, 3u * 4);
  EXPECT_EQ(bands[1].y1, 11);
  EXPECT_EQ(bands[1].zMax, 0.75f);
  const ReceiverBand both = unite(bands[0], bands[1]);
  EXPECT_EQ(both.matched, 8u * 4 - 1 + 3u * 4);
  EXPECT_EQ(both.y0, 1);
  EXPECT_EQ(both.y1, 11);
  EXPECT_EQ(both.zMin, 0.25f);
}

}  // namespace
}  // namespace penumbra::raster
