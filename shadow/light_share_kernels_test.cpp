#include "shadow/light_share_kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "core/random.h"
#include "shadow/intensity_transfer.h"
#include "tests/isa_params.h"

namespace penumbra::shadow {
namespace {

class LightShareKernelsOnTarget : public ::testing::TestWithParam<simd::Isa> {};

// Random sign and mantissa, exponent in +-span: sums that round differently in any other
// order, shares on both sides of the clamp, zeros and negatives (unlit channels).
struct RandomDoubles {
  uint64_t state;
  double next(int span) {
    state = core::splitmix64(state);
    const int exponent = int(state >> 58) % (2 * span + 1) - span;
    return std::ldexp(double(int64_t(state & 0xFFFFFFFFFFFFF) - (int64_t{1} << 51)) * 0x1.0p-51,
                      exponent);
  }
};

TEST_P(LightShareKernelsOnTarget, SumRowsMatchesTheScalarReferenceBitForBit) {
  const LightShareKernels& reference = lightShareKernelsFor(simd::Isa::kScalar);
  const LightShareKernels& kernels = lightShareKernelsFor(GetParam());
  RandomDoubles random{11};
  for (int trial = 0; trial < 400; ++trial) {
    const size_t count = size_t(trial % 9);    // no rows too: sums of 0
    const size_t n = size_t(trial * 7 % 200);  // every tail length, full 4-vector sweeps
    std::vector<std::vector<double>> data(count, std::vector<double>(n));
    std::vector<const double*> rows;
    for (auto& row : data) {
      for (double& x : row) x = random.next(30);
      rows.push_back(row.data());
    }
    std::vector<double> expected(n + 1, 5.0), actual(n + 1, 5.0);
    reference.sumRows(rows.data(), count, n, expected.data());
    kernels.sumRows(rows.data(), count, n, actual.data());
    ASSERT_EQ(std::memcmp(expected.data(), actual.data(), (n + 1) * sizeof(double)), 0)
        << simd::isaName(GetParam()) << ", trial " << trial;
  }
}

TEST_P(LightShareKernelsOnTarget, SharesMatchTheScalarReference) {
  const LightShareKernels& kernels = lightShareKernelsFor(GetParam());
  RandomDoubles random{12};
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Edge pairs first: unlit, clamped, exact halves of a level, NaN and infinities.
  std::vector<double> part{0.0,    -0.0, -1.0, 1.0, 2.0, 1.0, 0.5 / 65280,
                           1e-300, kInf, kInf, nan, 1.0, 1.0, 1e300};
  std::vector<double> whole{1.0,   1.0, 1.0,  0.0, 1.0, -1.0, 1.0,
                            1e300, 1.0, kInf, 1.0, nan, kInf, 1e-300};
  for (int i = 0; i < 20000; ++i) {
    part.push_back(random.next(8));
    whole.push_back(i % 4 == 0 ? part.back() * (1.0 + random.next(0) * 0x1.0p-40) : random.next(8));
  }
  for (size_t n : {part.size(), size_t{1}, size_t{7}, size_t{13}}) {
    std::vector<uint16_t> out(n + 1, 7);
    kernels.shares(part.data(), whole.data(), n, out.data());
    for (size_t j = 0; j < n; ++j) {
      ASSERT_EQ(out[j], lightShare(part[j], whole[j]))
          << simd::isaName(GetParam()) << ": " << part[j] << " of " << whole[j];
    }
    EXPECT_EQ(out[n], 7) << "nothing past n";
  }
}

INSTANTIATE_TEST_SUITE_P(AllTargets, LightShareKernelsOnTarget,
                         ::testing::ValuesIn(simd::supportedIsas()),
                         penumbra::testing::isaTestName);

}  // namespace
}  // namespace penumbra::shadow
