// The per-frame HDR merge (platform/bracket_merge.h): Debevec & Malik's weighted mean, exactly
// as written, in exposure order; the clipped cases; a provable error bound on a linear camera;
// tables from the portable exp (not libm); the same bytes every time, pinned by a hash.
#include "platform/bracket_merge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "envmap/portable_log_exp.h"

namespace penumbra::platform {
namespace {

// A BGR frame of width × height, rows `stride` bytes apart (padding 0xEE: never read).
struct Frame {
  uint32_t width = 0, height = 0;
  size_t stride = 0;
  std::vector<uint8_t> bytes;
  Frame(uint32_t w, uint32_t h) : width(w), height(h), stride(size_t(w) * 3 + 5) {
    bytes.assign(stride * h, 0xEE);
  }
  uint8_t* at(uint32_t x, uint32_t y) { return bytes.data() + stride * y + size_t(x) * 3; }
};

size_t mergeFrames(const BracketMerge& m, const std::vector<Frame>& frames, core::ImageF& out) {
  std::vector<const uint8_t*> data;
  std::vector<size_t> strides;
  for (const Frame& f : frames) {
    data.push_back(f.bytes.data());
    strides.push_back(f.stride);
  }
  return m.merge(data, strides, frames[0].width, frames[0].height, out);
}

// A linear camera (gamma 1: code z records z / 255, by the portable exp and log), 1 ms and
// 4 ms, exposure scale 2.
TEST(BracketMerge, WeightedMeanInExposureOrderAndTheClippedCases) {
  const std::vector<double> ms{1, 4};
  const BracketMerge m(curveResponse(1), ms, 2);
  ASSERT_EQ(m.exposures(), 2u);
  std::vector<Frame> frames{Frame(4, 1), Frame(4, 1)};
  // Pixel 0: unclipped in both (R, G, B differ). Pixel 1: 255 in the long exposure only.
  // Pixel 2: 255 in both (saturated). Pixel 3: 0 in both (dark).
  const uint8_t shortCodes[4][3] = {{40, 60, 100}, {90, 90, 90}, {255, 255, 10}, {0, 0, 0}};
  const uint8_t longCodes[4][3] = {{160, 230, 254}, {255, 255, 255}, {255, 255, 40}, {0, 0, 0}};
  for (uint32_t x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) {
      frames[0].at(x, 0)[2 - c] = shortCodes[x][c];  // BGR
      frames[1].at(x, 0)[2 - c] = longCodes[x][c];
    }
  core::ImageF out;
  EXPECT_EQ(mergeFrames(m, frames, out), 1u);  // pixel 2 only
  for (uint32_t x = 0; x < 4; ++x)
    for (size_t c = 0; c < 3; ++c) {
      const uint8_t z0 = shortCodes[x][c], z1 = longCodes[x][c];
      const float r0 = m.radiance(0)[c][z0], r1 = m.radiance(1)[c][z1];
      float want = 0;
      if (hatWeight(z0) + hatWeight(z1) > 0) {
        want = (0.0f + hatWeight(z0) * r0 + hatWeight(z1) * r1) / (hatWeight(z0) + hatWeight(z1));
      } else {
        want = z0 == 255 ? r0 : r1;  // the shortest's bound R_0(255), or the longest's
      }
      EXPECT_EQ(out.pixel(x, 0)[c], want) << x << " " << c;
    }
  EXPECT_EQ(out.pixel(1, 0)[0], m.radiance(0)[0][90]);  // only the short exposure counts
  EXPECT_EQ(out.pixel(2, 0)[0], 0.5f);                  // saturated: R_0(255) = 1 / 1 ms / 2
  EXPECT_EQ(out.pixel(3, 0)[0], 0.0f);                  // dark: the longest's code 0
  EXPECT_EQ(m.radiance(1)[0][255], float(1 / 4.0 / 2));
}

// A linear camera photographing radiance L at times Δt_j records z_j = round(255 · L · Δt_j)
// (clipped to 255). Each unclipped estimate z_j / 255 / Δt_j is within 0.5 / (255 · Δt_j) of
// L, and the merge is a convex combination of them, so it is within the largest such bound
// among the estimates it weights — the longest unclipped exposure's bound can only be smaller.
TEST(BracketMerge, LinearCameraIsRecoveredWithinTheCoarsestWeightedStep) {
  const std::vector<double> ms{0.25, 2, 16};
  const BracketMerge m(curveResponse(1), ms, 1);
  const uint32_t n = 2000;
  std::vector<Frame> frames(3, Frame(n, 1));
  std::vector<double> radiance(n);
  for (uint32_t i = 0; i < n; ++i) {
    radiance[i] = 0.01 * std::pow(1.005, double(i));  // 0.01 … 2.2e2: 4.3 decades
    for (size_t j = 0; j < 3; ++j) {
      const long z = std::lround(255 * std::min(1.0, radiance[i] * ms[j]));
      uint8_t* p = frames[j].at(i, 0);
      p[0] = p[1] = p[2] = uint8_t(z);
    }
  }
  core::ImageF out;
  const size_t saturated = mergeFrames(m, frames, out);
  size_t clipped = 0;
  for (uint32_t i = 0; i < n; ++i) {
    double bound = 0;
    bool any = false;
    for (size_t j = 0; j < 3; ++j) {
      const uint8_t z = frames[j].at(i, 0)[0];
      if (z > 0 && z < 255) bound = std::max(bound, 0.5 / (255 * ms[j])), any = true;
    }
    if (!any) {
      ++clipped;
      continue;
    }
    // + float rounding of the tables and the sum: a few ulp of the value.
    EXPECT_NEAR(out.pixel(i, 0)[1], radiance[i], bound + 1e-6 * radiance[i]) << radiance[i];
  }
  EXPECT_GT(clipped, 0u);  // the brightest are beyond the shortest exposure: 255 · L · 0.25 ms
  EXPECT_EQ(saturated, clipped);
}

// The tables come from envmap's portable exp, so they are the same bits on every machine.
TEST(BracketMerge, TablesComeFromThePortableExp) {
  kiosk::CameraResponseCurves curves;
  for (size_t c = 0; c < 3; ++c)
    for (size_t z = 0; z < 256; ++z)
      curves.logExposure[c][z] = (double(z) - 128) / 37.0 + 0.01 * double(c);
  const ChannelResponse response = calibratedResponse(curves);
  const std::vector<double> ms{0.05, 1.6, 51.2};
  const BracketMerge m(response, ms, 3);
  for (size_t j = 0; j < 3; ++j)
    for (size_t c = 0; c < 3; ++c)
      for (size_t z = 0; z < 256; ++z) {
        const double e = envmap::portableExp(curves.logExposure[c][z]);
        ASSERT_EQ(response[c][z], e);
        ASSERT_EQ(m.radiance(j)[c][z], float(e / ms[j] / 3)) << j << " " << c << " " << z;
      }
}

// FNV-1a over the merged image's bytes.
uint64_t hashOf(const core::ImageF& image) {
  uint64_t h = 0xcbf29ce484222325ull;
  const auto* bytes = reinterpret_cast<const uint8_t*>(image.pixels.data());
  for (size_t i = 0; i < image.pixels.size() * sizeof(float); ++i) {
    h = (h ^ bytes[i]) * 0x100000001b3ull;
  }
  return h;
}

// Counter-based codes (SplitMix64 of the exposure, pixel and channel).
std::vector<Frame> noiseBracket(uint32_t width, uint32_t height) {
  std::vector<Frame> frames(3, Frame(width, height));
  for (size_t j = 0; j < 3; ++j)
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x)
        for (size_t c = 0; c < 3; ++c) {
          uint64_t k = (uint64_t(j) << 48) ^ (uint64_t(y) << 32) ^ (uint64_t(x) << 8) ^ c;
          k += 0x9e3779b97f4a7c15ull;
          k = (k ^ (k >> 30)) * 0xbf58476d1ce4e5b9ull;
          k = (k ^ (k >> 27)) * 0x94d049bb133111ebull;
          k ^= k >> 31;
          // A quarter of the codes clipped bright, an eighth dark: every clip case occurs.
          const uint8_t z = (k & 3) == 0 ? 255 : ((k >> 2) & 7) == 0 ? 0 : uint8_t(k >> 56);
          frames[j].at(x, y)[c] = z;
        }
  return frames;
}

// The same bytes every time, and the bytes of this arithmetic (binary32 sums in exposure
// order, one division) pinned by a hash. After a deliberate change to the merge's arithmetic,
// update the hash in its own commit, saying why.
TEST(BracketMerge, SameBytesEveryTimePinnedByAHash) {
  // An S-shaped g from IEEE operations only (no libm), so the input is the same everywhere.
  kiosk::CameraResponseCurves curves;
  for (size_t c = 0; c < 3; ++c)
    for (size_t z = 0; z < 256; ++z) {
      const double t = (double(z) - 128) / 128;
      curves.logExposure[c][z] = 4 * t / (1.5 - t * t) + 0.01 * double(c);
    }
  const std::vector<double> ms{0.05, 1.6, 51.2};
  const BracketMerge m(calibratedResponse(curves), ms, 0.7);
  const std::vector<Frame> frames = noiseBracket(97, 61);
  core::ImageF a, b;
  const size_t saturated = mergeFrames(m, frames, a);
  EXPECT_EQ(mergeFrames(BracketMerge(calibratedResponse(curves), ms, 0.7), frames, b), saturated);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)), 0);
  EXPECT_GT(saturated, 0u);
  EXPECT_EQ(hashOf(a), 0xa17f8d8e3fd91ea3ull) << std::hex << hashOf(a);
}

TEST(BracketMerge, BadBracketsAreRefused) {
  const ChannelResponse r = curveResponse(0);
  EXPECT_THROW(BracketMerge(r, std::vector<double>{}, 1), std::invalid_argument);
  EXPECT_THROW(BracketMerge(r, std::vector<double>{2, 2}, 1), std::invalid_argument);
  EXPECT_THROW(BracketMerge(r, std::vector<double>{4, 2}, 1), std::invalid_argument);
  EXPECT_THROW(BracketMerge(r, std::vector<double>{0, 2}, 1), std::invalid_argument);
  EXPECT_THROW(BracketMerge(r, std::vector<double>{1, 2}, 0), std::invalid_argument);
  const BracketMerge m(r, std::vector<double>{1, 2}, 1);
  const std::vector<Frame> one(1, Frame(2, 2));
  core::ImageF out;
  EXPECT_THROW(mergeFrames(m, one, out), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::platform
