// The environment camera's per-frame work on the board before any light is sampled (Havran
// et al. 2005 §3, issue 16): three 480 × 480 exposures merged into radiance (Debevec & Malik's
// weighted mean, platform/bracket_merge.h), and one exposure linearised through its response
// table and resampled into the hemisphere map (envmap/fisheye_resampler.h). One core each.
//   build/ci/bin/penumbra_environment_camera_bench
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "bench/benchmark_main.h"
#include "core/image.h"
#include "envmap/fisheye_resampler.h"
#include "envmap/hemisphere_map.h"
#include "platform/bracket_merge.h"
#include "platform/environment_response.h"

namespace penumbra {
namespace {

constexpr uint32_t kSize = 480;

// Pseudo-random BGR codes (splitmix64 of the position), a quarter clipped bright and an eighth
// dark, so that the merge takes each of its branches about as often as a bright room makes it.
std::vector<uint8_t> noiseFrame(uint32_t exposure) {
  std::vector<uint8_t> bytes(size_t(kSize) * kSize * 3);
  for (size_t i = 0; i < bytes.size(); ++i) {
    uint64_t k = (uint64_t(exposure) << 48) ^ i;
    k += 0x9e3779b97f4a7c15ull;
    k = (k ^ (k >> 30)) * 0xbf58476d1ce4e5b9ull;
    k = (k ^ (k >> 27)) * 0x94d049bb133111ebull;
    k ^= k >> 31;
    bytes[i] = (k & 3) == 0 ? 255 : ((k >> 2) & 7) == 0 ? 0 : uint8_t(k >> 56);
  }
  return bytes;
}

void BM_BracketMerge3x480(benchmark::State& state) {
  const std::vector<double> ms{0.05, 1.6, 51.2};
  const platform::BracketMerge merge(platform::curveResponse(0), ms, 1);
  const std::vector<std::vector<uint8_t>> frames{noiseFrame(0), noiseFrame(1), noiseFrame(2)};
  const std::vector<const uint8_t*> data{frames[0].data(), frames[1].data(), frames[2].data()};
  const std::vector<size_t> strides(3, size_t(kSize) * 3);
  core::ImageF out;
  for (auto _ : state) {
    benchmark::DoNotOptimize(merge.merge(data, strides, kSize, kSize, out));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kSize * kSize);
}
BENCHMARK(BM_BracketMerge3x480)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LineariseAndResample480(benchmark::State& state) {
  const std::vector<uint8_t> bgr = noiseFrame(0);
  const platform::ChannelTables table = platform::radianceTables(platform::curveResponse(0), 1, 1);
  const envmap::FisheyeResampler resampler(envmap::FisheyeLens::equidistant180(kSize));
  core::ImageF image;
  envmap::HemisphereMap map;
  for (auto _ : state) {
    platform::linearise(bgr.data(), size_t(kSize) * 3, kSize, kSize, table, image);
    resampler.resample(image, map);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_LineariseAndResample480)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  return penumbra::bench::benchmarkMain("penumbra_environment_camera_bench", argc, argv);
}
