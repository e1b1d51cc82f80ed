// Exhaustive checks of the exact 8-bit ops on every compiled and supported target.
#include "simd/u8_ops.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "tests/isa_params.h"

namespace penumbra::simd {
namespace {

TEST(ProductU8, ScalarFormulaIsRoundedDivisionBy255) {
  for (uint32_t a = 0; a < 256; ++a) {
    for (uint32_t b = 0; b < 256; ++b) {
      // round(a*b/255) with exact integers: floor((2ab + 255) / 510).
      const uint32_t expected = (2 * a * b + 255) / 510;
      ASSERT_EQ(productU8(uint8_t(a), uint8_t(b)), expected) << a << " * " << b;
      const uint32_t t = a * b + 128;
      ASSERT_EQ((t + (t >> 8)) >> 8, expected) << "Blinn form, " << a << " * " << b;
    }
  }
}

TEST(ProductU8, OftenQuotedFormulaIsWrong) {
  // Documented pitfall (design §6): (t + (t >> 8) + 0x80) >> 8 with t = a*b mis-rounds.
  int wrong = 0;
  for (uint32_t a = 0; a < 256; ++a) {
    for (uint32_t b = 0; b < 256; ++b) {
      const uint32_t t = a * b;
      wrong += ((t + (t >> 8) + 0x80) >> 8) != productU8(uint8_t(a), uint8_t(b));
    }
  }
  EXPECT_EQ(wrong, 24);
}

// Fixed-point accumulation (spec §8): each pass's amount is S·W/65536 rounded half up, in
// u32 without overflow up to S = 65280, W = 65536; the umbra (W = 65536) gives S exactly.
TEST(Fixed8_8, AmountIsRoundedToOne256thOfALevel) {
  for (uint32_t s = 0; s <= 65280; s += 17) {
    for (uint32_t w : {0u, 1u, 255u, 256u, 32767u, 32768u, 40000u, 65535u, 65536u}) {
      const uint64_t exact2 = 2 * uint64_t{s} * w;  // twice S·W, to round half up exactly
      const uint64_t expected = (exact2 + 65536) / 131072;
      ASSERT_EQ(fineAmount(s, w), expected) << s << " * " << w;
    }
    ASSERT_EQ(fineAmount(s, 65536), s);
  }
  ASSERT_EQ(fineAmount(65280, 65536), 65280u);
  EXPECT_EQ(fixed8_8Levels(127), 0u);
  EXPECT_EQ(fixed8_8Levels(128), 1u);
  EXPECT_EQ(fixed8_8Levels(65535), 256u);
}

class U8OpsOnTarget : public ::testing::TestWithParam<Isa> {};

TEST_P(U8OpsOnTarget, AllPairsMatchScalar) {
  const U8Ops& ops = u8OpsFor(GetParam());
  std::vector<uint8_t> a(65536), b(65536), out(65536), m(65536);
  for (uint32_t i = 0; i < 65536; ++i) {
    a[i] = uint8_t(i >> 8);
    b[i] = uint8_t(i);
  }
  ops.product(a.data(), b.data(), out.data(), out.size());
  for (uint32_t i = 0; i < 65536; ++i) ASSERT_EQ(out[i], productU8(a[i], b[i])) << i;
  ops.subtractSaturate(a.data(), b.data(), out.data(), out.size());
  for (uint32_t i = 0; i < 65536; ++i) ASSERT_EQ(out[i], subtractSaturateU8(a[i], b[i])) << i;
  // dst - round(s*m/255) for every (s, m) at several dst values.
  for (uint32_t dst : {0u, 1u, 77u, 128u, 254u, 255u}) {
    std::vector<uint8_t> d(65536, uint8_t(dst));
    ops.subtractMasked(d.data(), a.data(), b.data(), d.size());
    for (uint32_t i = 0; i < 65536; ++i) {
      ASSERT_EQ(d[i], subtractMaskedU8(uint8_t(dst), a[i], b[i])) << i;
    }
  }
  // Odd lengths exercise the tails.
  for (size_t n : {size_t{0}, size_t{1}, size_t{7}, size_t{33}, size_t{127}}) {
    std::vector<uint8_t> o(n + 1, 0xAB);
    ops.product(a.data() + 1000, b.data() + 1000, o.data(), n);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(o[i], productU8(a[1000 + i], b[1000 + i]));
    ASSERT_EQ(o[n], 0xAB) << "wrote past the end";
  }
}

INSTANTIATE_TEST_SUITE_P(AllTargets, U8OpsOnTarget, ::testing::ValuesIn(supportedIsas()),
                         penumbra::testing::isaTestName);

}  // namespace
}  // namespace penumbra::simd
