#include "shadow/irradiance_volume.h"
#include "core/random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "scene/sha256.h"
#include "tests/isa_params.h"

namespace penumbra::shadow {
namespace {

// A 2x2x2 volume over the unit cube whose vertex v holds a constant (direction-independent)
// E/pi of value[v]: only coefficient 0 is set, to value / Y_0.
IrradianceVolume constantCube(const std::array<float, 8>& value) {
  IrradianceVolume vol;
  vol.dims = {2, 2, 2};
  vol.origin = glm::vec3(0.0f);
  vol.spacing = glm::vec3(1.0f);
  vol.coefficients.assign(8 * kShFloats, 0.0f);
  vol.valid.assign(8, 1);
  for (size_t v = 0; v < 8; ++v) {
    for (size_t ch = 0; ch < 3; ++ch) {
      vol.coefficients[v * kShFloats + ch] = value[v] / 0.282095f;
    }
  }
  return vol;
}

TEST(IrradianceVolumeLookup, TrilinearBetweenConstantVertices) {
  // Value = x + 2y + 4z at the corners: trilinear reproduces it inside.
  std::array<float, 8> value{};
  for (int v = 0; v < 8; ++v) value[size_t(v)] = float((v & 1) + 2 * ((v >> 1) & 1) + 4 * (v >> 2));
  const IrradianceVolume vol = constantCube(value);
  vol.validate();
  const glm::vec3 p(0.25f, 0.5f, 0.75f);
  const glm::vec3 e = vol.irradianceOverPi(p, glm::vec3(0, 0, 1));
  EXPECT_NEAR(e.x, 0.25 + 1.0 + 3.0, 1e-5);
  EXPECT_EQ(e.x, e.y);
  // Outside the grid: clamped to the nearest face.
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(-5, -5, -5), glm::vec3(1, 0, 0)).x, 0.0, 1e-6);
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(9, 9, 9), glm::vec3(1, 0, 0)).x, 7.0, 1e-5);
}

TEST(IrradianceVolumeLookup, InvalidCornersAreLeftOutAndWeightsRenormalized) {
  std::array<float, 8> value{};
  value.fill(1.0f);
  value[0] = 100.0f;  // inside a desk: must not leak
  IrradianceVolume vol = constantCube(value);
  vol.valid[0] = 0;
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(0.1f, 0.1f, 0.1f), glm::vec3(0, 1, 0)).x, 1.0, 1e-5);
  // Every corner invalid: the fallback.
  vol.valid.assign(8, 0);
  vol.fallback = {};
  vol.fallback[1] = 2.0f / 0.282095f;
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(0.5f), glm::vec3(0, 1, 0)).y, 2.0, 1e-5);
}

TEST(IrradianceVolumeLookup, DirectionalBandOneFollowsTheNormal) {
  IrradianceVolume vol = constantCube({1, 1, 1, 1, 1, 1, 1, 1});
  // Add a +y gradient in band 1 (coefficient 1 multiplies Y = 0.488603 y).
  for (size_t v = 0; v < 8; ++v) vol.coefficients[v * kShFloats + 3] = 0.5f / 0.488603f;
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(0.5f), glm::vec3(0, 1, 0)).x, 1.5, 1e-5);
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(0.5f), glm::vec3(0, -1, 0)).x, 0.5, 1e-5);
  EXPECT_NEAR(vol.irradianceOverPi(glm::vec3(0.5f), glm::vec3(0, -1, 0)).y, 1.0, 1e-5);
}

TEST(IrradianceVolumeLookup, NegativeReconstructionIsClampedAndNanPositionsAreSafe) {
  IrradianceVolume vol = constantCube({1, 1, 1, 1, 1, 1, 1, 1});
  for (size_t v = 0; v < 8; ++v) vol.coefficients[v * kShFloats + 3] = 3.0f / 0.488603f;
  EXPECT_EQ(vol.irradianceOverPi(glm::vec3(0.5f), glm::vec3(0, -1, 0)).x, 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const glm::vec3 e = vol.irradianceOverPi(glm::vec3(nan, 0.5f, 0.5f), glm::vec3(0, 0, 1));
  EXPECT_TRUE(std::isfinite(e.x));
}

TEST(IrradianceVolumeLookup, ValidateRejectsBadVolumes) {
  IrradianceVolume vol = constantCube({1, 1, 1, 1, 1, 1, 1, 1});
  EXPECT_NO_THROW(vol.validate());
  IrradianceVolume bad = vol;
  bad.coefficients.pop_back();
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad = vol;
  bad.coefficients[5] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad = vol;
  bad.spacing.y = 0.0f;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad = vol;
  bad.valid.resize(3);
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad = vol;
  bad.dims.z = 0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(IrradianceVolumeShading, ReflectanceToneAndBatchIndependence) {
  const IrradianceVolume vol = constantCube({0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f});
  const ToneCurve tone = ToneCurve::gamma(1.0, 1.0);  // linear: 255 L
  std::vector<core::Vec3> positions;
  std::vector<glm::vec3> normals;
  for (int i = 0; i < 100; ++i) {
    positions.push_back({float(i % 10) * 0.1f, float(i / 10) * 0.1f, 0.3f});
    normals.push_back(glm::vec3(float(i % 3) - 1.0f, 1.0f, float(i % 7) * 0.2f));
  }
  normals[5] = glm::vec3(0.0f);  // degenerate normal: +y
  std::vector<core::Rgb8> all(100), one(1);
  std::vector<glm::vec3> radiance(100);
  shadeVerticesDiffuse(vol, positions, normals, glm::vec3(1.0f, 0.5f, 0.0f), tone, all, radiance);
  EXPECT_NEAR(radiance[0].x, 0.5, 1e-5);
  EXPECT_NEAR(radiance[0].y, 0.25, 1e-5);
  EXPECT_EQ(radiance[0].z, 0.0f);
  EXPECT_EQ(all[0].r, tone(0.5));
  // One vertex at a time gives the same bytes as the batch.
  for (size_t v = 0; v < 100; ++v) {
    shadeVerticesDiffuse(vol, std::span(positions).subspan(v, 1), std::span(normals).subspan(v, 1),
                         glm::vec3(1.0f, 0.5f, 0.0f), tone, one, {});
    EXPECT_EQ(one[0], all[v]);
  }
  std::vector<core::Rgb8> wrong(3);
  EXPECT_THROW(shadeVerticesDiffuse(vol, positions, normals, glm::vec3(1.0f), tone, wrong, {}),
               std::invalid_argument);
}

// Every target's corner blend gives the scalar reference's bits (design §3), for full-mantissa
// records and weights (where a fused multiply-add or another summation order would round
// differently), zero weights, and signed zeros; and writes nothing past the 27 outputs.
class ShCornerBlendOnTarget : public ::testing::TestWithParam<simd::Isa> {};

TEST_P(ShCornerBlendOnTarget, MatchesTheScalarReferenceBitForBit) {
  const ShCornerBlend reference = shCornerBlendFor(simd::Isa::kScalar);
  const ShCornerBlend blend = shCornerBlendFor(GetParam());
  uint64_t state = 7;
  auto next = [&](int exponentSpan) {  // random sign and mantissa, exponent in +-exponentSpan
    state = core::splitmix64(state);
    const int exponent = int(state >> 58) % (2 * exponentSpan + 1) - exponentSpan;
    return std::ldexp(float(int32_t(state & 0xFFFFFF) - (1 << 23)) * 0x1.0p-23f, exponent);
  };
  std::vector<float> records(8 * kShFloats);
  for (int trial = 0; trial < 2000; ++trial) {
    for (float& r : records) r = next(20);
    const float* record[8];
    float weight[8];
    float weightSum = 0.0f;
    for (int c = 0; c < 8; ++c) {
      record[c] = &records[size_t(c) * kShFloats];
      weight[c] = trial % 3 == 0 && c % 3 == 1 ? 0.0f : std::fabs(next(2));
      weightSum = weightSum + weight[c];
    }
    if (trial % 5 == 0) records[3] = -0.0f;
    float expected[kShFloats + 1], actual[kShFloats + 1];
    expected[kShFloats] = actual[kShFloats] = 123.0f;
    reference(record, weight, 1.0f / weightSum, expected);
    blend(record, weight, 1.0f / weightSum, actual);
    ASSERT_EQ(std::memcmp(expected, actual, sizeof expected), 0)
        << simd::isaName(GetParam()) << ", trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(AllTargets, ShCornerBlendOnTarget,
                         ::testing::ValuesIn(simd::supportedIsas()),
                         penumbra::testing::isaTestName);

// The bit-exact contract (design §3) for product shading: a golden hash of the radiance
// and colours of 2,000 vertices shaded from a pseudo-random volume. The same on every ISA
// and compiler that honours -ffp-contract=off (checked natively and under qemu-aarch64);
// a change here is a deliberate, explained commit.
TEST(IrradianceVolumeShading, GoldenBytes) {
  IrradianceVolume vol;
  vol.dims = {5, 4, 6};
  vol.origin = {0.25f, 0.2f, 0.3f};
  vol.spacing = {0.5f, 0.6f, 0.45f};
  uint64_t state = 42;
  auto next = [&] {
    state = core::splitmix64(state);
    return float(int64_t(state >> 40) - (int64_t{1} << 23)) * 0x1.0p-22f;  // exact, in [-2, 2)
  };
  for (size_t i = 0; i < vol.vertexCount() * kShFloats; ++i) vol.coefficients.push_back(next());
  for (size_t i = 0; i < vol.vertexCount(); ++i) vol.valid.push_back(next() > -1.5f);
  for (float& f : vol.fallback) f = next();
  std::vector<core::Vec3> positions;
  std::vector<glm::vec3> normals;
  for (int i = 0; i < 2000; ++i) {
    positions.push_back({next() + 1.2f, next() + 1.0f, next() + 1.4f});
    normals.push_back({next(), next(), next()});
  }
  const ToneCurve tone = ToneCurve::gamma(1.2, 2.2);
  std::vector<core::Rgb8> colours(positions.size());
  std::vector<glm::vec3> radiance(positions.size());
  shadeVerticesDiffuse(vol, positions, normals, glm::vec3(0.7f, 0.5f, 0.3f), tone, colours,
                       radiance);
  std::vector<uint8_t> bytes(radiance.size() * sizeof(glm::vec3) + colours.size() * 3);
  std::memcpy(bytes.data(), radiance.data(), radiance.size() * sizeof(glm::vec3));
  std::memcpy(bytes.data() + radiance.size() * sizeof(glm::vec3), colours.data(),
              colours.size() * 3);
  EXPECT_EQ(scene::sha256Hex(bytes),
            "37f72e97a1fdccb798dc7c429137e53ee4029ef5007d1b01cc189a0d9c2f152b");
}

}  // namespace
}  // namespace penumbra::shadow
