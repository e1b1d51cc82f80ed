// Every target of raster/occluder_setup.h against the scalar functions of
// raster/triangle_setup.h, value for value: snapped vertices, accepted triangles and every
// field of their set-up (edges, bias, box, depth plane bits).
#include "raster/occluder_setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "tests/isa_params.h"

namespace penumbra::raster {
namespace {

uint32_t bitsOf(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

class OccluderSetupOnTarget : public ::testing::TestWithParam<simd::Isa> {};

// A perspective light looking down -z at points around the origin, as a pass's light.
core::Mat4 lightMatrix(std::mt19937& rng) {
  std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
  core::Mat4 m;
  const float f = 1.5f + jitter(rng), n = 0.5f, far = 20.0f;
  m.m = {f,
         jitter(rng) * 0.1f,
         jitter(rng),
         jitter(rng),
         jitter(rng) * 0.1f,
         f,
         jitter(rng),
         jitter(rng),
         0,
         0,
         -(far + n) / (far - n),
         -2 * far * n / (far - n) + 3.0f,
         0,
         0,
         -1,
         3.0f};
  return m;
}

TEST_P(OccluderSetupOnTarget, SnapInsideMatchesScalar) {
  const OccluderKernels& ref = occluderKernelsFor(simd::Isa::kScalar);
  const OccluderKernels& k = occluderKernelsFor(GetParam());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-0.9f, 0.9f);
  size_t compared = 0;
  for (size_t count : {0, 1, 7, 15, 16, 17, 33, 200}) {
    for (int round = 0; round < 20; ++round) {
      const core::Mat4 m = lightMatrix(rng);
      std::vector<core::Vec3> points(count);
      for (core::Vec3& p : points) p = {coord(rng), coord(rng), coord(rng)};
      const uint32_t size = round % 2 ? 256 : 1024;
      const size_t padded = (count + kOccluderBatch - 1) / kOccluderBatch * kOccluderBatch;
      std::vector<int32_t> xr(padded), yr(padded), xs(padded), ys(padded);
      std::vector<float> zr(padded), zs(padded);
      const bool insideRef =
          ref.snapInside(m, points.data(), count, size, xr.data(), yr.data(), zr.data());
      ASSERT_EQ(k.snapInside(m, points.data(), count, size, xs.data(), ys.data(), zs.data()),
                insideRef);
      if (!insideRef) continue;
      for (size_t i = 0; i < count; ++i) {
        ASSERT_EQ(xs[i], xr[i]) << "count " << count << " vertex " << i;
        ASSERT_EQ(ys[i], yr[i]) << "count " << count << " vertex " << i;
        ASSERT_EQ(bitsOf(zs[i]), bitsOf(zr[i])) << "count " << count << " vertex " << i;
      }
      compared += count;
    }
  }
  EXPECT_GT(compared, 5000u);  // the points were inside: the comparison ran
}

// One vertex outside any of the seven clip planes, or NaN, anywhere in the batch (also in
// a partial last batch) makes every target answer false.
TEST_P(OccluderSetupOnTarget, SnapInsideRefusesAnyOutsideVertex) {
  const OccluderKernels& k = occluderKernelsFor(GetParam());
  std::mt19937 rng(11);
  const core::Mat4 m = lightMatrix(rng);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const core::Vec3 outside[] = {{0, 0, 4.0f}, {0, 0, -40.0f}, {30, 0, 0},  {-30, 0, 0},
                                {0, 30, 0},   {0, -30, 0},    {nan, 0, 0}, {0, 0, nan}};
  for (size_t count : {1, 16, 21}) {
    for (const core::Vec3& bad : outside) {
      for (size_t at : {size_t{0}, count / 2, count - 1}) {
        std::vector<core::Vec3> points(count, core::Vec3{0.1f, -0.2f, 0.3f});
        points[at] = bad;
        std::vector<int32_t> x(32), y(32);
        std::vector<float> z(32);
        EXPECT_FALSE(k.snapInside(m, points.data(), count, 256, x.data(), y.data(), z.data()))
            << "count " << count << " bad vertex at " << at << " (" << bad.x << ", " << bad.y
            << ", " << bad.z << ")";
      }
    }
  }
}

void expectSameTriangle(const SetupTriangle& a, const SetupTriangle& b, size_t index) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(a.v[c].x, b.v[c].x) << index;
    EXPECT_EQ(a.v[c].y, b.v[c].y) << index;
    EXPECT_EQ(bitsOf(a.v[c].z), bitsOf(b.v[c].z)) << index;
    EXPECT_EQ(a.v[c].w, b.v[c].w) << index;
    EXPECT_EQ(a.edges[c].a, b.edges[c].a) << index;
    EXPECT_EQ(a.edges[c].b, b.edges[c].b) << index;
    EXPECT_EQ(a.edges[c].c, b.edges[c].c) << index;
    EXPECT_EQ(a.edges[c].bias, b.edges[c].bias) << index;
  }
  EXPECT_EQ(a.det, b.det) << index;
  EXPECT_EQ(a.minX, b.minX) << index;
  EXPECT_EQ(a.minY, b.minY) << index;
  EXPECT_EQ(a.maxX, b.maxX) << index;
  EXPECT_EQ(a.maxY, b.maxY) << index;
  EXPECT_EQ(bitsOf(a.depth.z00), bitsOf(b.depth.z00)) << index;
  EXPECT_EQ(bitsOf(a.depth.dzdx), bitsOf(b.depth.dzdx)) << index;
  EXPECT_EQ(bitsOf(a.depth.dzdy), bitsOf(b.depth.dzdy)) << index;
}

// Random vertices over the whole guard band of a 4096 map (the largest the trace format
// allows) and of a 256 map, with shared coordinates (horizontal and vertical edges),
// collinear and repeated vertices, triangles between pixel centres and off the map.
TEST_P(OccluderSetupOnTarget, SetupTrianglesMatchesScalar) {
  const OccluderKernels& ref = occluderKernelsFor(simd::Isa::kScalar);
  const OccluderKernels& k = occluderKernelsFor(GetParam());
  std::mt19937 rng(3);
  size_t accepted = 0, culledAccepted = 0, offered = 0;
  for (uint32_t size : {256u, 4096u}) {
    const int32_t band = static_cast<int32_t>(5 * 128 * size);  // |x| of a guard-band vertex
    for (int scale : {40, 800, 20000, band}) {
      std::uniform_int_distribution<int32_t> near(-scale, scale);
      std::uniform_int_distribution<int32_t> centre(0, static_cast<int32_t>(256 * size));
      std::uniform_real_distribution<float> depth(0.0f, 1.0f);
      const size_t vertices = 300;
      std::vector<int32_t> x(vertices), y(vertices);
      std::vector<float> z(vertices);
      // Vertices 0..59 make slivers between two rows (or columns) of pixel centres: wide
      // but covering no centre in y (or in x), which setupTriangle refuses.
      std::uniform_int_distribution<int32_t> gap(129, 383), wide(-2000, 2000);
      for (size_t i = 0; i < 60; ++i) {
        const int32_t base = 256 * static_cast<int32_t>(i % 5 + 3);
        const int32_t along = 256 * 40 + wide(rng), across = base + gap(rng);
        x[i] = i < 30 ? along : across;
        y[i] = i < 30 ? across : along;
        z[i] = 0.5f;
      }
      for (size_t i = 60; i < vertices; ++i) {
        const int32_t cx = centre(rng), cy = centre(rng);
        x[i] = std::clamp(cx + near(rng), -band, band);
        y[i] = std::clamp(cy + near(rng), -band, band);
        if (i % 7 == 3) y[i] = y[i - 1];                   // horizontal edges
        if (i % 11 == 5) x[i] = x[i - 2];                  // vertical edges
        if (i % 13 == 8) x[i] = 128 + 256 * (x[i] / 256);  // on a pixel centre
        z[i] = depth(rng);
      }
      std::uniform_int_distribution<uint32_t> pick(0, vertices - 1);
      for (size_t count : {0, 1, 3, 8, 9, 16, 17, 250}) {
        std::vector<uint32_t> indices(3 * count);
        for (size_t t = 0; t < count; ++t) {
          if (t % 4 == 1) {  // a sliver: three vertices of one group of five
            const uint32_t group = 30 * (pick(rng) % 2) + pick(rng) % 5;
            for (int c = 0; c < 3; ++c) indices[3 * t + c] = group + 5 * (pick(rng) % 6);
            continue;
          }
          const uint32_t a = pick(rng);
          indices[3 * t] = a;
          indices[3 * t + 1] = t % 9 == 4 ? a : pick(rng);  // degenerate: repeated vertex
          indices[3 * t + 2] = pick(rng);
        }
        for (const bool cull : {false, true}) {
          std::vector<SetupTriangle> expected(count), actual(count);
          const size_t n = ref.setupTriangles(x.data(), y.data(), z.data(), indices.data(), count,
                                              size, cull, expected.data());
          ASSERT_EQ(k.setupTriangles(x.data(), y.data(), z.data(), indices.data(), count, size,
                                     cull, actual.data()),
                    n)
              << "size " << size << " scale " << scale << " count " << count << " cull " << cull;
          for (size_t t = 0; t < n; ++t) expectSameTriangle(expected[t], actual[t], t);
          (cull ? culledAccepted : accepted) += n;
          if (!cull) offered += count;
        }
      }
    }
  }
  // Both outcomes occur: most triangles are accepted, some are refused; culling keeps the
  // ones of one winding, about half of them.
  EXPECT_GT(accepted, offered / 2);
  EXPECT_LT(accepted, offered);
  EXPECT_GT(culledAccepted, accepted / 3);
  EXPECT_LT(culledAccepted, 2 * accepted / 3);
}

INSTANTIATE_TEST_SUITE_P(AllTargets, OccluderSetupOnTarget,
                         ::testing::ValuesIn(simd::supportedIsas()),
                         penumbra::testing::isaTestName);

}  // namespace
}  // namespace penumbra::raster
