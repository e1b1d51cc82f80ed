#include "reference/flip.h"

#include <gtest/gtest.h>

#include <numeric>

namespace penumbra::reference {
namespace {

std::vector<uint8_t> grey(uint32_t w, uint32_t h, uint8_t v) {
  return std::vector<uint8_t>(size_t(w) * h * 3, v);
}

double mean(const std::vector<float>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

TEST(Flip, IdenticalImagesGiveZero) {
  std::vector<uint8_t> a(24 * 20 * 3);
  for (size_t i = 0; i < a.size(); ++i) a[i] = uint8_t((i * 53) % 256);
  for (float f : flipErrorMap(a, a, 24, 20)) ASSERT_EQ(f, 0.0f);
}

// Uniform black against uniform white: no features, colour term only. HyAB = 100 (ΔL only),
// 100^0.7 = 25.1 lies above the knee p_c·cmax (cmax = HyAB(green, blue)^0.7 ≈ 41.2), so
// ΔE ≈ 0.95 + (25.1 − 16.5)/(41.2 − 16.5)·0.05 ≈ 0.967.
TEST(Flip, BlackAgainstWhiteIsCloseToOne) {
  const std::vector<float> m = flipErrorMap(grey(16, 16, 0), grey(16, 16, 255), 16, 16);
  for (float f : m) {
    ASSERT_GT(f, 0.95f);
    ASSERT_LE(f, 1.0f);
  }
  EXPECT_NEAR(m[0], 0.967, 0.005);
}

TEST(Flip, SymmetricForUniformImages) {
  const auto ab = flipErrorMap(grey(8, 8, 40), grey(8, 8, 90), 8, 8);
  const auto ba = flipErrorMap(grey(8, 8, 90), grey(8, 8, 40), 8, 8);
  EXPECT_NEAR(ab[27], ba[27], 1e-6);
}

// Monotone in the size of a change: a darker square (a shadow) of growing side on a grey
// floor, and a fixed square of growing depth.
TEST(Flip, MonotoneInTheSizeOfAChange) {
  const uint32_t w = 48, h = 48;
  const std::vector<uint8_t> ref = grey(w, h, 160);
  auto withSquare = [&](uint32_t side, uint8_t value) {
    std::vector<uint8_t> t = ref;
    for (uint32_t y = 24 - side / 2; y < 24 - side / 2 + side; ++y) {
      for (uint32_t x = 24 - side / 2; x < 24 - side / 2 + side; ++x) {
        for (int k = 0; k < 3; ++k) t[(size_t(y) * w + x) * 3 + size_t(k)] = value;
      }
    }
    return t;
  };
  double last = 0;
  for (uint32_t side : {2u, 6u, 12u, 20u, 32u}) {
    const double m = mean(flipErrorMap(ref, withSquare(side, 100), w, h));
    EXPECT_GT(m, last) << "side " << side;
    last = m;
  }
  last = 0;
  for (int depth : {2, 8, 20, 50, 100, 160}) {
    const double m = mean(flipErrorMap(ref, withSquare(16, uint8_t(160 - depth)), w, h));
    EXPECT_GT(m, last) << "depth " << depth;
    last = m;
  }
}

// Fewer pixels per degree = the same pixels seen larger: a one-pixel change is more visible.
TEST(Flip, OnePixelChangeIsMoreVisibleAtLowerPpd) {
  std::vector<uint8_t> t = grey(21, 21, 128);
  for (int k = 0; k < 3; ++k) t[(10 * 21 + 10) * 3 + size_t(k)] = 200;
  const auto far = flipErrorMap(grey(21, 21, 128), t, 21, 21, {67.0});
  const auto near = flipErrorMap(grey(21, 21, 128), t, 21, 21, {10.0});
  EXPECT_GT(near[10 * 21 + 10], far[10 * 21 + 10]);
}

TEST(Flip, RejectsMismatchedBuffers) {
  EXPECT_THROW(flipErrorMap(grey(4, 4, 0), grey(4, 3, 0), 4, 4), std::invalid_argument);
  EXPECT_THROW(flipErrorMap({}, {}, 0, 0), std::invalid_argument);
  EXPECT_THROW(flipErrorMap(grey(4, 4, 0), grey(4, 4, 0), 4, 4, {0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
