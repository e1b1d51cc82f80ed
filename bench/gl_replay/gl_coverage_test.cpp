// Pixel coverage of snapped triangles: raster::coverageMask() (spec §4) against Mesa's
// rasterizer (llvmpipe), exactly, on seeded random triangles of every awkward kind.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench/gl_replay/gl_coverage.h"
#include "bench/gl_replay/gl_test_context.h"
#include "raster/triangle_setup.h"

namespace penumbra::gl {
namespace {

using raster::SnappedVertex;
using Triangle = std::array<SnappedVertex, 3>;

constexpr uint32_t kSide = 128;
constexpr int32_t kOne = 256;  // sub-pixel units per pixel

SnappedVertex vertex(int32_t x, int32_t y) {
  SnappedVertex v;
  v.x = x;
  v.y = y;
  return v;
}

// Seeded triangles in a 128 x 128 image, sub-pixel coordinates (1/256 px, y down).
// Large ones stay inside [-384, 512] px, within GlCoverage's 8x viewport, so Mesa never
// clips them (see gl_coverage.cpp).
std::vector<Triangle> randomTriangles(uint32_t seed, int perKind) {
  std::mt19937 rng(seed);
  auto uniform = [&](int32_t lo, int32_t hi) {  // [lo, hi]
    return std::uniform_int_distribution<int32_t>(lo, hi)(rng);
  };
  const int32_t span = static_cast<int32_t>(kSide) * kOne;
  auto anywhere = [&] { return vertex(uniform(0, span - 1), uniform(0, span - 1)); };
  auto centre = [&] {
    return vertex(uniform(0, kSide - 1) * kOne + kOne / 2, uniform(0, kSide - 1) * kOne + kOne / 2);
  };
  std::vector<Triangle> out;
  for (int i = 0; i < perKind; ++i) {
    // Tiny: within a few pixels, often covering nothing or one pixel centre.
    const SnappedVertex a = anywhere();
    out.push_back({a, vertex(a.x + uniform(-700, 700), a.y + uniform(-700, 700)),
                   vertex(a.x + uniform(-700, 700), a.y + uniform(-700, 700))});
    // Thin: a long sliver, the third vertex a few units off the segment.
    const SnappedVertex b = anywhere(), c = anywhere();
    const int32_t t = uniform(0, 1024);
    out.push_back({b, c,
                   vertex(b.x + (c.x - b.x) / 1024 * t + uniform(-3, 3),
                          b.y + (c.y - b.y) / 1024 * t + uniform(-3, 3))});
    // Large: well beyond the image on several sides.
    auto far = [&] { return vertex(uniform(-3 * span, 4 * span), uniform(-3 * span, 4 * span)); };
    out.push_back({far(), far(), far()});
    // Axis-aligned edges (horizontal and vertical), corners on pixel-centre lines half the
    // time so edges run exactly through pixel centres.
    {
      SnappedVertex p = uniform(0, 1) ? centre() : anywhere();
      SnappedVertex q = uniform(0, 1) ? centre() : anywhere();
      const int shape = uniform(0, 2);
      if (shape == 0)
        out.push_back({p, vertex(q.x, p.y), vertex(p.x, q.y)});
      else if (shape == 1)
        out.push_back({p, vertex(q.x, p.y), q});
      else
        out.push_back({p, vertex(p.x, q.y), anywhere()});
    }
    // Shared-edge pairs: the two halves of a random quad (and the pair must not overlap
    // on the shared edge: checked through coverageMask equality on both).
    {
      const SnappedVertex p = anywhere(), q = anywhere(), r = anywhere(), s = anywhere();
      out.push_back({p, q, r});
      out.push_back({p, r, s});
    }
    // All vertices exactly on pixel centres.
    out.push_back({centre(), centre(), centre()});
    // Vertices on the half-pixel lattice (centres and corners): many E = 0 ties.
    auto half = [&] {
      return vertex(uniform(0, 2 * kSide) * (kOne / 2), uniform(0, 2 * kSide) * (kOne / 2));
    };
    out.push_back({half(), half(), half()});
  }
  return out;
}

// (ostringstream: GCC 12 warns falsely on chained std::string operator+ under -O2.)
std::string describe(const Triangle& t) {
  std::ostringstream s;
  for (const SnappedVertex& v : t) s << "(" << v.x << ", " << v.y << ") ";
  return s.str();
}

size_t countDiffering(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += (a[i] != 0) != (b[i] != 0) ? 1 : 0;
  return n;
}

TEST(GlCoverage, MatchesLlvmpipeExactly) {
  PENUMBRA_REQUIRE_GL();
  GlCoverage gl(kSide, kSide, YMapping::kDirect);
  const std::vector<Triangle> triangles = randomTriangles(20261122, 300);
  size_t mismatches = 0, coveredPixels = 0;
  for (const Triangle& t : triangles) {
    const std::vector<uint8_t> ours = raster::coverageMask(t, kSide, kSide);
    const std::vector<uint8_t> mesa = gl.mask(t);
    ASSERT_EQ(ours.size(), mesa.size());
    for (uint8_t c : ours) coveredPixels += c != 0 ? 1 : 0;
    const size_t differing = countDiffering(ours, mesa);
    if (differing != 0) {
      ++mismatches;
      ADD_FAILURE() << "triangle " << describe(t) << ": " << differing
                    << " pixels differ from llvmpipe";
    }
  }
  std::cout << "[ coverage ] " << triangles.size() << " triangles in " << kSide << "x" << kSide
            << ", " << coveredPixels << " covered pixels, " << mismatches
            << " mismatching triangles vs llvmpipe\n";
  RecordProperty("triangles", static_cast<int>(triangles.size()));
  RecordProperty("mismatches", static_cast<int>(mismatches));
  EXPECT_GE(triangles.size(), 2000u);
  EXPECT_EQ(mismatches, 0u);
}

// The evidence for YMapping::kDirect: handing GL the mirrored picture (its natural
// bottom-left origin) turns our horizontal "top" edges into bottom edges, and llvmpipe
// then disagrees on pixel centres lying exactly on horizontal edges.
TEST(GlCoverage, MirroredMappingBreaksHorizontalEdgeTies) {
  PENUMBRA_REQUIRE_GL();
  GlCoverage mirrored(kSide, kSide, YMapping::kMirror);
  GlCoverage direct(kSide, kSide, YMapping::kDirect);
  // A right triangle whose horizontal edge runs exactly through the centres of row 10.
  const Triangle t = {vertex(10 * kOne + 128, 10 * kOne + 128),
                      vertex(40 * kOne + 128, 10 * kOne + 128),
                      vertex(10 * kOne + 128, 30 * kOne + 128)};
  const std::vector<uint8_t> ours = raster::coverageMask(t, kSide, kSide);
  EXPECT_EQ(countDiffering(ours, direct.mask(t)), 0u);
  EXPECT_GT(countDiffering(ours, mirrored.mask(t)), 0u);
  // Row 10 lies on the top edge: ours covers it (top-left rule).
  EXPECT_EQ(ours[10 * kSide + 20], 1);
}

}  // namespace
}  // namespace penumbra::gl
