// Live lighting's bit-exact contract (design §3; docs/live-lighting.md): the whole per-frame
// chain — CDF and inverse-transform sampling, temporal filter, clustering, tone mapping — is
// scalar binary64/binary32 arithmetic in a fixed order with no libm, so a synthetic noisy
// sequence gives the same bytes on every ISA (this binary runs under qemu-aarch64 in CI) and
// whatever thread runs it. Golden hash below; after a deliberate change to the arithmetic,
// update it in its own commit, saying why.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/job_pool.h"
#include "core/random.h"
#include "envmap/envmap_sampling.h"
#include "envmap/light_clustering.h"
#include "envmap/light_filter.h"
#include "envmap/reinhard_tonemap.h"
#include "scene/sha256.h"

namespace penumbra {
namespace {

using namespace envmap;

void append(std::vector<uint8_t>& bytes, const void* data, size_t size) {
  const auto* p = static_cast<const uint8_t*>(data);
  bytes.insert(bytes.end(), p, p + size);
}

// 24 frames of a sky with a window, 5% per-sample noise keyed by `seed`: 300 lights, filtered,
// clustered to ≤ 72, and the map tone-mapped; every light's id, direction and power and every
// tone-mapped byte appended.
std::vector<uint8_t> liveLightingBytes(uint64_t seed) {
  const SamplePattern pattern(300);
  TemporalLightFilter filter;
  ReinhardToneMapper toneMapper({0.0, 0.1, 1e-4});
  std::vector<uint8_t> bytes;
  for (uint64_t frame = 0; frame < 24; ++frame) {
    HemisphereMap map{core::ImageF(kEnvmapCols, kEnvmapRows)};
    for (uint32_t y = 0; y < kEnvmapRows; ++y)
      for (uint32_t x = 0; x < kEnvmapCols; ++x) {
        const bool window = x >= 70 && x < 110 && y >= 40 && y < 60;
        const float sky = 1.0f - 0.5f * float(y) / kEnvmapRows;
        const float base[3] = {window ? 40.0f : 0.6f * sky, window ? 36.0f : 0.8f * sky,
                               window ? 28.0f : sky};
        for (int c = 0; c < 3; ++c) {
          const uint64_t sample = (uint64_t(y) * kEnvmapCols + x) * 3 + uint64_t(c);
          map.radiance.pixel(x, y)[c] =
              base[c] * float(1.0 + 0.05 * (2 * core::unitSample(seed * 1000 + frame, sample) - 1));
        }
      }
    const LightClusters clusters =
        clusterLights(filter.push(EnvmapDistribution(map).sample(pattern, 300)), 72);
    for (const DirectionalLight& light : clusters.lights) {
      append(bytes, &light.id, sizeof light.id);
      append(bytes, &light.direction, sizeof light.direction);
      append(bytes, &light.power, sizeof light.power);
    }
    const core::Image8 display = toneMapper.map(map.radiance);
    append(bytes, display.pixels.data(), display.pixels.size());
  }
  return bytes;
}

TEST(LiveLightingInvariance, SameBytesOnEveryIsaAndThreadCount) {
  constexpr size_t kSequences = 4;
  std::vector<std::string> reference(kSequences);
  for (size_t s = 0; s < kSequences; ++s) reference[s] = scene::sha256Hex(liveLightingBytes(s));
  // Golden: measured on x86-64 (AVX-512 machine, g++ 12, ci preset); aarch64 must agree.
  EXPECT_EQ(reference[0], "429fa74a3786eb3665993bfe5efbcea74d009e571c7fce241ca6c645716c468f");
  for (int threads : {2, 4}) {
    core::JobPool pool(threads);
    std::vector<std::string> hashes(kSequences);
    pool.parallelFor(kSequences,
                     [&](size_t s, int) { hashes[s] = scene::sha256Hex(liveLightingBytes(s)); });
    EXPECT_EQ(hashes, reference) << threads << " threads";
  }
}

}  // namespace
}  // namespace penumbra
