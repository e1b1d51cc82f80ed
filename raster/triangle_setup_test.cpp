// Coverage: fill rule, watertightness, clipping and degenerate input (spec §3–4).
#include "raster/triangle_setup.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>

namespace penumbra::raster {
namespace {

SnappedVertex sv(int32_t x, int32_t y) {
  SnappedVertex v;
  v.x = x;
  v.y = y;
  v.w = {65536, 0, 0};
  return v;
}

int countCovered(const std::vector<uint8_t>& mask) {
  int n = 0;
  for (uint8_t m : mask) n += m;
  return n;
}

TEST(FillRule, PixelCentresOnEdgesFollowTopLeft) {
  // Square with corners exactly on pixel centres (2.5, 2.5)-(6.5, 6.5), split on a diagonal
  // through pixel centres. Top-left rule: top and left edges in, bottom and right out,
  // the shared diagonal in exactly one triangle.
  const int32_t a = 2 * 256 + 128, b = 6 * 256 + 128;
  const auto t1 = coverageMask({sv(a, a), sv(b, a), sv(b, b)}, 10, 10);
  const auto t2 = coverageMask({sv(a, a), sv(b, b), sv(a, b)}, 10, 10);
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 10; ++x) {
      const int n = t1[10 * y + x] + t2[10 * y + x];
      const bool inside = x >= 2 && x < 6 && y >= 2 && y < 6;
      EXPECT_EQ(n, inside ? 1 : 0) << x << "," << y;
    }
  }
}

TEST(FillRule, WindingDoesNotMatter) {
  const auto cw = coverageMask({sv(100, 200), sv(2000, 900), sv(700, 2400)}, 12, 12);
  const auto ccw = coverageMask({sv(100, 200), sv(700, 2400), sv(2000, 900)}, 12, 12);
  EXPECT_EQ(cw, ccw);
  EXPECT_GT(countCovered(cw), 0);
}

TEST(Coverage, DegenerateAndTinyTriangles) {
  EXPECT_EQ(countCovered(coverageMask({sv(300, 300), sv(900, 900), sv(1500, 1500)}, 8, 8)), 0);
  EXPECT_EQ(countCovered(coverageMask({sv(300, 300), sv(300, 300), sv(300, 300)}, 8, 8)), 0);
  // A sub-pixel triangle around a pixel centre covers exactly it; one beside it nothing.
  EXPECT_EQ(countCovered(coverageMask({sv(380, 370), sv(390, 390), sv(370, 390)}, 8, 8)), 1);
  EXPECT_EQ(countCovered(coverageMask({sv(260, 260), sv(270, 260), sv(260, 270)}, 8, 8)), 0);
}

TEST(Coverage, HugeTriangleCoversEverything) {
  const int32_t big = 1 << 21;
  EXPECT_EQ(countCovered(coverageMask({sv(-big, -big), sv(big, -big), sv(0, big)}, 64, 48)),
            64 * 48);
}

// A jittered grid of shared vertices, larger than the image: every pixel exactly once.
TEST(Watertight, SharedEdgesCoveredExactlyOnce) {
  std::mt19937 rng(42);
  std::uniform_int_distribution<int32_t> jitter(-200, 200);
  const int n = 9;
  const uint32_t w = 96, h = 80;
  std::vector<SnappedVertex> grid;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      const int32_t x = -512 + i * int32_t(w + 4) * 256 / n + (border ? 0 : jitter(rng) * 3);
      const int32_t y = -512 + j * int32_t(h + 4) * 256 / n + (border ? 0 : jitter(rng) * 3);
      grid.push_back(sv(x, y));
    }
  }
  std::vector<int> count(size_t{w} * h, 0);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const SnappedVertex& a = grid[j * (n + 1) + i];
      const SnappedVertex& b = grid[j * (n + 1) + i + 1];
      const SnappedVertex& c = grid[(j + 1) * (n + 1) + i + 1];
      const SnappedVertex& d = grid[(j + 1) * (n + 1) + i];
      // Alternate the diagonal so both diagonal directions are exercised.
      const bool flip = (i + j) % 2 == 0;
      const std::array<std::array<SnappedVertex, 3>, 2> tris =
          flip ? std::array<std::array<SnappedVertex, 3>, 2>{{{a, b, c}, {a, c, d}}}
               : std::array<std::array<SnappedVertex, 3>, 2>{{{a, b, d}, {b, c, d}}};
      for (const auto& t : tris) {
        const auto m = coverageMask(t, w, h);
        for (size_t k = 0; k < m.size(); ++k) count[k] += m[k];
      }
    }
  }
  for (size_t k = 0; k < count.size(); ++k) ASSERT_EQ(count[k], 1) << "pixel " << k;
}

// A fan around a vertex with many thin slivers: still exactly once.
TEST(Watertight, FanOfSlivers) {
  const uint32_t w = 64, h = 64;
  const int32_t cx = 32 * 256 + 77, cy = 31 * 256 + 200;
  const int spokes = 97;
  std::vector<SnappedVertex> rim;
  for (int k = 0; k < spokes; ++k) {
    const double a = 2.0 * 3.14159265358979 * k / spokes;
    rim.push_back(sv(cx + int32_t(std::lround(std::cos(a) * 90 * 256)),
                     cy + int32_t(std::lround(std::sin(a) * 90 * 256))));
  }
  std::vector<int> count(size_t{w} * h, 0);
  for (int k = 0; k < spokes; ++k) {
    const auto m = coverageMask({sv(cx, cy), rim[k], rim[(k + 1) % spokes]}, w, h);
    for (size_t i = 0; i < m.size(); ++i) count[i] += m[i];
  }
  for (size_t i = 0; i < count.size(); ++i) ASSERT_EQ(count[i], 1) << "pixel " << i;
}

TEST(Spans, RowWalkerEqualsRowSpanOnEveryRow) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3000; ++trial) {
    // Mix small, large and far off-screen triangles; many with horizontal edges.
    const int32_t range = trial % 3 == 0 ? (1 << 22) : (trial % 3 == 1 ? 80 * 256 : 4 * 256);
    std::uniform_int_distribution<int32_t> coord(-range / 2, range);
    std::array<SnappedVertex, 3> v{sv(coord(rng), coord(rng)), sv(coord(rng), coord(rng)),
                                   sv(coord(rng), coord(rng))};
    if (trial % 5 == 0) v[1].y = v[0].y;
    SetupTriangle t;
    if (!setupTriangle(v, 80, 60, t)) continue;
    RowWalker walker(t, t.minY);
    for (int32_t y = t.minY; y < t.maxY; ++y, walker.nextRow()) {
      int32_t xa = -1, xb = -1, wa = -1, wb = -1;
      const bool expected = rowSpan(t, y, 5, 77, xa, xb);
      ASSERT_EQ(walker.span(5, 77, wa, wb), expected) << "trial " << trial << " row " << y;
      if (expected) {
        ASSERT_EQ(wa, xa);
        ASSERT_EQ(wb, xb);
      }
    }
  }
}

// Spec §4–5 written out directly (integer quotients by / and %, two scalar binary64
// divisions, det tested before the box): setupTriangle, which tests the box first, uses
// shifts and one two-lane division, must give the same answer and the same fields.
bool referenceSetup(const std::array<SnappedVertex, 3>& vin, uint32_t width, uint32_t height,
                    SetupTriangle& t) {
  auto floorDiv = [](int64_t n, int64_t d) { return n / d - (n % d != 0 && n < 0 ? 1 : 0); };
  auto ceilDiv = [](int64_t n, int64_t d) { return n / d + (n % d != 0 && n > 0 ? 1 : 0); };
  t.v = vin;
  t.det = int64_t{t.v[1].x - t.v[0].x} * (t.v[2].y - t.v[0].y) -
          int64_t{t.v[2].x - t.v[0].x} * (t.v[1].y - t.v[0].y);
  if (t.det == 0) return false;
  if (t.det < 0) {
    std::swap(t.v[1], t.v[2]);
    t.det = -t.det;
  }
  for (int i = 0; i < 3; ++i) {
    const SnappedVertex& a = t.v[i];
    const SnappedVertex& b = t.v[(i + 1) % 3];
    t.edges[i].a = int64_t{a.y} - b.y;
    t.edges[i].b = int64_t{b.x} - a.x;
    t.edges[i].c = int64_t{a.x} * b.y - int64_t{a.y} * b.x;
    t.edges[i].bias = t.edges[i].a > 0 || (t.edges[i].a == 0 && t.edges[i].b > 0) ? 0 : 1;
  }
  int64_t loX = t.v[0].x, hiX = t.v[0].x, loY = t.v[0].y, hiY = t.v[0].y;
  for (const SnappedVertex& v : t.v) {
    loX = std::min<int64_t>(loX, v.x);
    hiX = std::max<int64_t>(hiX, v.x);
    loY = std::min<int64_t>(loY, v.y);
    hiY = std::max<int64_t>(hiY, v.y);
  }
  t.minX = static_cast<int32_t>(std::max<int64_t>(0, ceilDiv(loX - 128, 256)));
  t.maxX = static_cast<int32_t>(std::min<int64_t>(width, floorDiv(hiX - 128, 256) + 1));
  t.minY = static_cast<int32_t>(std::max<int64_t>(0, ceilDiv(loY - 128, 256)));
  t.maxY = static_cast<int32_t>(std::min<int64_t>(height, floorDiv(hiY - 128, 256) + 1));
  if (t.minX >= t.maxX || t.minY >= t.maxY) return false;
  const double det = static_cast<double>(t.det);
  const double dx1 = t.v[1].x - t.v[0].x, dy1 = t.v[1].y - t.v[0].y;
  const double dx2 = t.v[2].x - t.v[0].x, dy2 = t.v[2].y - t.v[0].y;
  const double z0 = t.v[0].z;
  const double dz1 = static_cast<double>(t.v[1].z) - z0, dz2 = static_cast<double>(t.v[2].z) - z0;
  const double gX = (dz1 * dy2 - dz2 * dy1) / det;
  const double gY = (dz2 * dx1 - dz1 * dx2) / det;
  const double zc =
      z0 + gX * (256.0 * t.minX + 128.0 - t.v[0].x) + gY * (256.0 * t.minY + 128.0 - t.v[0].y);
  t.depth.z00 = static_cast<float>(zc);
  t.depth.dzdx = static_cast<float>(gX * 256.0);
  t.depth.dzdy = static_cast<float>(gY * 256.0);
  return true;
}

TEST(Setup, MatchesTheDirectFormulasFieldForField) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> depth(0.0f, 1.0f);
  int drawn = 0, rejected = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    // Tiny (sub-pixel, many without a pixel centre), map-sized and guard-band-sized
    // triangles, some with centres exactly on pixel-centre boundaries, some degenerate.
    const int32_t range = trial % 4 == 0 ? (1 << 22) : (trial % 4 == 1 ? 300 * 256 : 3 * 256);
    const int32_t base = trial % 4 == 0 ? -(1 << 21) : -256;
    std::uniform_int_distribution<int32_t> coord(base, base + range);
    std::array<SnappedVertex, 3> v;
    for (SnappedVertex& p : v) {
      p = sv(coord(rng), coord(rng));
      if (trial % 7 == 0) p.x = (p.x & ~255) + 128;  // on a pixel centre column
      p.z = depth(rng);
    }
    if (trial % 11 == 0) v[2] = v[1];  // det = 0
    SetupTriangle a, b;
    const bool ra = referenceSetup(v, 256, 240, a);
    const bool rb = setupTriangle(v, 256, 240, b);
    ASSERT_EQ(ra, rb) << "trial " << trial;
    if (!ra) {
      ++rejected;
      continue;
    }
    ++drawn;
    ASSERT_EQ(a.det, b.det);
    ASSERT_EQ(a.minX, b.minX);
    ASSERT_EQ(a.maxX, b.maxX);
    ASSERT_EQ(a.minY, b.minY);
    ASSERT_EQ(a.maxY, b.maxY);
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(a.v[i].x, b.v[i].x);
      ASSERT_EQ(a.v[i].y, b.v[i].y);
      ASSERT_EQ(a.edges[i].a, b.edges[i].a);
      ASSERT_EQ(a.edges[i].b, b.edges[i].b);
      ASSERT_EQ(a.edges[i].c, b.edges[i].c);
      ASSERT_EQ(a.edges[i].bias, b.edges[i].bias);
    }
    // Bit patterns: the same binary32 values, not merely equal ones.
    ASSERT_EQ(std::bit_cast<uint32_t>(a.depth.z00), std::bit_cast<uint32_t>(b.depth.z00));
    ASSERT_EQ(std::bit_cast<uint32_t>(a.depth.dzdx), std::bit_cast<uint32_t>(b.depth.dzdx));
    ASSERT_EQ(std::bit_cast<uint32_t>(a.depth.dzdy), std::bit_cast<uint32_t>(b.depth.dzdy));
  }
  EXPECT_GT(drawn, 50000);
  EXPECT_GT(rejected, 20000);
}

// Spec §5's attribute plane with every origin quotient in 128 bits; attributePlane takes
// an int64 quotient when the numerator fits, which must not change a bit.
AttributePlane referencePlane(const SetupTriangle& t, const std::array<uint8_t, 3>& corners) {
  __extension__ typedef __int128 Int128;
  auto roundDiv = [](Int128 n, Int128 d) {  // floor((2n + d) / 2d), d > 0
    const Int128 num = 2 * n + d, den = 2 * d;
    const Int128 q = num / den;
    return num % den != 0 && num < 0 ? q - 1 : q;
  };
  std::array<Int128, 3> v;
  for (int i = 0; i < 3; ++i) {
    v[i] = Int128{t.v[i].w[0]} * corners[0] + Int128{t.v[i].w[1]} * corners[1] +
           Int128{t.v[i].w[2]} * corners[2];
  }
  const Int128 dv1 = v[1] - v[0], dv2 = v[2] - v[0];
  const Int128 nX = dv1 * (t.v[2].y - t.v[0].y) - dv2 * (t.v[1].y - t.v[0].y);
  const Int128 nY = dv2 * (t.v[1].x - t.v[0].x) - dv1 * (t.v[2].x - t.v[0].x);
  const Int128 ox = Int128{256} * t.minX + 128 - t.v[0].x;
  const Int128 oy = Int128{256} * t.minY + 128 - t.v[0].y;
  const Int128 c = v[0] + roundDiv(nX * ox + nY * oy, t.det);
  return {static_cast<uint32_t>(static_cast<uint64_t>(c)),
          static_cast<uint32_t>(static_cast<uint64_t>(roundDiv(256 * nX, t.det))),
          static_cast<uint32_t>(static_cast<uint64_t>(roundDiv(256 * nY, t.det)))};
}

TEST(Setup, AttributePlaneMatches128BitQuotients) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int32_t> weight(0, 65536);
  int checked = 0, wide = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    // Guard-band-sized triangles (origin numerators beyond 2^61, the 128-bit path) and
    // small ones (the int64 path), with clipped-vertex weights.
    const int32_t range = trial % 3 == 0 ? (1 << 22) : (trial % 3 == 1 ? 40 * 256 : 600 * 256);
    std::uniform_int_distribution<int32_t> coord(-range / 2, range);
    std::array<SnappedVertex, 3> v;
    for (SnappedVertex& p : v) {
      p = sv(coord(rng), coord(rng));
      const int32_t w1 = weight(rng), w2 = weight(rng) % (65537 - w1);
      p.w = {65536 - w1 - w2, w1, w2};
    }
    SetupTriangle t;
    if (!setupTriangle(v, 4096, 4096, t)) continue;
    const std::array<uint8_t, 3> corners{uint8_t(byte(rng)), uint8_t(byte(rng)),
                                         uint8_t(byte(rng))};
    const AttributePlane a = referencePlane(t, corners), b = attributePlane(t, corners);
    ASSERT_EQ(a.c, b.c) << trial;
    ASSERT_EQ(a.gx, b.gx) << trial;
    ASSERT_EQ(a.gy, b.gy) << trial;
    ++checked;
    const double ox = 256.0 * t.minX + 128 - t.v[0].x;
    wide += std::abs(ox) > double(1 << 20) ? 1 : 0;
  }
  EXPECT_GT(checked, 50000);
  EXPECT_GT(wide, 1000);
}

TEST(Spans, TileClassificationIsExact) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int32_t> coord(-4000, 70 * 256);
  for (int trial = 0; trial < 300; ++trial) {
    SetupTriangle t;
    if (!setupTriangle(
            {sv(coord(rng), coord(rng)), sv(coord(rng), coord(rng)), sv(coord(rng), coord(rng))},
            64, 64, t)) {
      continue;
    }
    for (int32_t ty = 0; ty < 64; ty += 16) {
      for (int32_t tx = 0; tx < 64; tx += 16) {
        int covered = 0;
        for (int32_t y = ty; y < ty + 16; ++y) {
          int32_t xa, xb;
          if (rowSpan(t, y, tx, tx + 16, xa, xb)) covered += xb - xa;
        }
        const TileCoverage c = classifyTile(t, tx, ty, tx + 16, ty + 16);
        if (c == TileCoverage::kNone) {
          ASSERT_EQ(covered, 0);
        }
        if (c == TileCoverage::kFull) {
          ASSERT_EQ(covered, 256);
        }
      }
    }
  }
}

ClipVertex cv(float x, float y, float z, float w) {
  return {x, y, z, w};
}

TEST(Clipping, NearPlaneCrossingKeepsTheVisiblePart) {
  std::vector<std::array<SnappedVertex, 3>> out;
  // One vertex behind the camera (w < 0): clipped to a quad, drawn as a fan of two.
  clipAndSnapTriangle(
      {cv(-0.5f, -0.5f, 0.5f, 1.0f), cv(0.5f, -0.5f, 0.5f, 1.0f), cv(0.0f, 0.5f, -3.0f, -1.0f)}, 64,
      64, out);
  ASSERT_EQ(out.size(), 2u);
  for (const auto& tri : out) {
    for (const SnappedVertex& v : tri) {
      EXPECT_GE(v.z, 0.0f);
      EXPECT_EQ(v.w[0] + v.w[1] + v.w[2], 65536);
    }
  }
}

TEST(Clipping, FullyOutsideAndOffscreenAreDiscarded) {
  std::vector<std::array<SnappedVertex, 3>> out;
  clipAndSnapTriangle({cv(0, 0, -2, -1), cv(1, 0, -2, -1), cv(0, 1, -2, -1)}, 64, 64, out);
  EXPECT_TRUE(out.empty());
  clipAndSnapTriangle({cv(10, 10, 0, 1), cv(11, 10, 0, 1), cv(10, 11, 0, 1)}, 64, 64, out);
  EXPECT_TRUE(out.empty());
}

TEST(Clipping, GuardBandBoundsSnappedCoordinates) {
  std::vector<std::array<SnappedVertex, 3>> out;
  clipAndSnapTriangle({cv(-1e6f, -1e6f, 0, 1), cv(1e6f, -1e6f, 0, 1), cv(0, 1e6f, 0, 1)}, 4096,
                      4096, out);
  ASSERT_FALSE(out.empty());
  for (const auto& tri : out) {
    for (const SnappedVertex& v : tri) {
      EXPECT_LT(std::abs(v.x), 1 << 23);
      EXPECT_LT(std::abs(v.y), 1 << 23);
    }
  }
}

// Spec §3, snapping range: whatever binary32 values a triangle has (extreme, Inf, NaN), every
// vertex that reaches the integer setup is inside the range §4-5 are proved for. Before the
// check, a clipped vertex of a matrix with an element of 2^31 or 1e9 (issue 18) snapped to
// INT32_MIN and setupTriangle overflowed.
void expectEveryVertexInSnappingRange(const std::vector<std::array<SnappedVertex, 3>>& out) {
  constexpr int32_t kLimit = 1 << 22;
  for (const auto& tri : out) {
    for (const SnappedVertex& v : tri) {
      ASSERT_LE(std::abs(v.x), kLimit);
      ASSERT_LE(std::abs(v.y), kLimit);
      ASSERT_TRUE(v.z >= 0.0f && v.z <= 1.0f);
      ASSERT_EQ(v.w[0] + v.w[1] + v.w[2], 65536);
      for (int32_t w : v.w) ASSERT_LE(std::abs(w), 3 * 65536);
    }
    SetupTriangle t;
    setupTriangle(tri, 4096, 4096, t);  // UBSan: no overflow in the setup either
  }
}

TEST(Clipping, ExtremeValuesNeverLeaveTheSnappingRange) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  constexpr float kMax = std::numeric_limits<float>::max();
  const float extremes[] = {0.0f,  1.0f,   -1.0f, 1e-5f, -1e-5f, 1e9f,  -1e9f,        2147483647.0f,
                            3e38f, -3e38f, kMax,  -kMax, kInf,   -kInf, std::nanf("")};
  // One vertex takes every combination of one extreme x, w and z; the two others are an
  // ordinary visible edge, so the triangle is clipped rather than rejected.
  size_t drawn = 0;
  for (float x : extremes) {
    for (float w : extremes) {
      for (float z : {0.0f, 1e9f, -kInf}) {
        std::vector<std::array<SnappedVertex, 3>> out;
        clipAndSnapTriangle(
            {cv(-0.5f, -0.5f, 0.5f, 1.0f), cv(0.5f, -0.5f, 0.5f, 1.0f), cv(x, x, z, w)}, 4096, 4096,
            out);
        expectEveryVertexInSnappingRange(out);
        drawn += out.size();
      }
    }
  }
  EXPECT_GT(drawn, 0u);  // the ordinary combinations are still drawn
}

TEST(Clipping, LargeMatrixElementsOfIssue18AreDrawnOrDiscardedWithinRange) {
  // A camera matrix with m[14] = 2^31 - 1 and a light matrix with an element of 1e9, applied
  // to a triangle crossing the near plane.
  core::Mat4 camera{};
  camera.m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 2147483647.0f, 0};
  core::Mat4 light{};
  light.m = {1, 0, 0, 0, 0, 1e9f, 0, 0, 0, 0, 1, 0, 0, 0, -1, 1};
  const core::Vec3 corners[] = {{-1, -1, 1e-3f}, {1, -1, -1}, {0, 1e-12f, 1e30f}};
  for (const core::Mat4& m : {camera, light}) {
    for (uint32_t size : {16u, 256u, 4096u}) {
      std::vector<std::array<SnappedVertex, 3>> out;
      clipAndSnapTriangle({transformPoint(m, corners[0]), transformPoint(m, corners[1]),
                           transformPoint(m, corners[2])},
                          size, size, out);
      expectEveryVertexInSnappingRange(out);
    }
  }
}

TEST(Attributes, PlaneReproducesVertexValuesAndStaysInRange) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int32_t> coord(0, 40 * 256);
  std::uniform_int_distribution<int> value(0, 255);
  for (int trial = 0; trial < 200; ++trial) {
    SetupTriangle t;
    if (!setupTriangle(
            {sv(coord(rng), coord(rng)), sv(coord(rng), coord(rng)), sv(coord(rng), coord(rng))},
            40, 40, t)) {
      continue;
    }
    // With every vertex weight on corner 0, the plane is constant.
    const uint8_t c = static_cast<uint8_t>(value(rng));
    const AttributePlane p = attributePlane(t, {c, static_cast<uint8_t>(value(rng)), 0});
    for (int32_t y = t.minY; y < t.maxY; ++y) {
      int32_t xa, xb;
      if (!rowSpan(t, y, 0, 40, xa, xb)) continue;
      for (int32_t x = xa; x < xb; ++x) {
        const uint32_t v = p.c + p.gx * uint32_t(x - t.minX) + p.gy * uint32_t(y - t.minY);
        const int32_t a = static_cast<int32_t>(v + 0x8000u) >> 16;
        ASSERT_EQ(a, c);
      }
    }
  }
}

}  // namespace
}  // namespace penumbra::raster
