// Google Benchmark suite: per-pixel cost of each hot kernel on each target, and whole
// frames. Speed targets live here (and in `penumbra bench-replay`), never in unit tests.
//   build/release/bin/penumbra_bench --benchmark_filter=MaskSubtract
#include <benchmark/benchmark.h>

#include <array>
#include <filesystem>
#include <random>
#include <utility>
#include <vector>

#include "bench/benchmark_main.h"
#include "raster/renderer.h"
#include "raster/shadow_map.h"
#include "raster/span_kernels.h"
#include "simd/u8_ops.h"
#include "tests/test_scenes.h"

namespace penumbra {
namespace {

constexpr int32_t kRun = 256;

void BM_ProductU8(benchmark::State& state, simd::Isa isa) {
  std::vector<uint8_t> a(1 << 16), b(1 << 16), out(1 << 16);
  for (size_t i = 0; i < a.size(); ++i) {
    a[i] = uint8_t(i >> 8);
    b[i] = uint8_t(i);
  }
  const simd::U8Ops& ops = simd::u8OpsFor(isa);
  for (auto _ : state) {
    ops.subtractMasked(out.data(), a.data(), b.data(), out.size());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(out.size()));
}

// One 64x4-pixel block of the mask sweep of a pass (spec §6 step 4, §7): every pixel
// marked, each looks up a 256x256 shadow map; `pcf` selects the 2x2 filter.
void BM_AccumulateRows(benchmark::State& state, simd::Isa isa, bool pcf) {
  constexpr int32_t kRows = 4, kWidth = 64;
  std::vector<float> depth(kWidth * kRows, 0.5f);
  std::vector<uint32_t> s(kWidth * kRows);
  raster::ShadowMap map;
  map.reset(256);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> d(0.3f, 0.7f);
  for (int32_t j = 0; j < 256; ++j) {
    for (int32_t i = 0; i < 256; ++i) map.origin()[j * map.stride() + i] = d(rng);
  }
  raster::ShadowLookup lookup{};
  lookup.p[0] = 0.9f;
  lookup.p[5] = 0.9f;
  lookup.p[3] = 3.0f;
  lookup.p[7] = 40.0f;
  lookup.p[10] = 1.0f;
  lookup.p[15] = 1.0f;
  lookup.map = map.origin();
  lookup.size = 256;
  lookup.stride = map.stride();
  lookup.bias = 0.001f;
  lookup.pcf2x2 = pcf;
  const std::vector<int32_t> xa(kRows, 0), xb(kRows, kWidth);
  std::vector<uint16_t> acc(3 * kWidth * kRows);
  const raster::SpanKernels& k = raster::spanKernelsFor(isa);
  for (auto _ : state) {
    std::fill(s.begin(), s.end(), 0x141414u);
    k.accumulateRows(depth.data(), s.data(), acc.data(), kWidth * kRows, kWidth, 0, kRows,
                     xa.data(), xb.data(), lookup);
    benchmark::DoNotOptimize(acc.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kWidth * kRows);
}

void BM_DepthLess(benchmark::State& state, simd::Isa isa) {
  std::vector<float> depth(kRun);
  raster::SpanPlanes p{};
  p.depth = {0.5f, 0.0001f, 0.0002f};
  const raster::SpanKernels& k = raster::spanKernelsFor(isa);
  for (auto _ : state) {
    std::fill(depth.begin(), depth.end(), 1.0f);
    benchmark::DoNotOptimize(k.depthLess(depth.data(), nullptr, 0, kRun, 3, p, 0));
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kRun);
}

// Depth-only triangles into a 256x256 shadow map (spec §6 step 1), each at most
// `state.range(0)` pixels wide and tall: 4 and 8 take the 4x4 and 2x8 blocks on 16-lane
// targets, 16 and 48 the one-row blocks, 160 the large-triangle path. Items are triangles;
// px_per_triangle counts the pixels that passed the depth test.
void BM_DepthTriangle(benchmark::State& state, simd::Isa isa) {
  const int32_t extent = int32_t(state.range(0)) * 256;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int32_t> corner(0, 256 * 256 - extent), offset(0, extent);
  std::uniform_real_distribution<float> z(0.0f, 1.0f);
  std::vector<raster::SetupTriangle> triangles;
  while (triangles.size() < 512) {
    const int32_t x0 = corner(rng), y0 = corner(rng);
    std::array<raster::SnappedVertex, 3> v;
    for (auto& p : v) {
      p.x = x0 + offset(rng);
      p.y = y0 + offset(rng);
      p.z = z(rng);
    }
    raster::SetupTriangle t;
    if (raster::setupTriangle(v, 256, 256, t)) triangles.push_back(t);
  }
  raster::ShadowMap map;
  map.reset(256);
  const raster::SpanKernels& k = raster::spanKernelsFor(isa);
  uint64_t pixels = 0;
  for (auto _ : state) {
    state.PauseTiming();  // clearing 256 KB would outweigh 512 small triangles
    map.clear(0, 0, 256, 256);
    state.ResumeTiming();
    for (const raster::SetupTriangle& t : triangles) {
      pixels += k.depthTriangle(map.origin(), nullptr, size_t(map.stride()), t, 0);
    }
    benchmark::DoNotOptimize(map.origin());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(triangles.size()));
  state.counters["px_per_triangle"] =
      double(pixels) / double(state.iterations()) / double(triangles.size());
}

// S of one receiver triangle's runs (spec §5, §6 step 4): 12 rows of 20-pixel runs
// (the showroom's receivers are mostly this short), ids 3 in 4 matching. `perRow` calls
// interpolateS once per row (before round 3), otherwise interpolateRuns once. Items are
// run pixels.
void BM_InterpolateRuns(benchmark::State& state, simd::Isa isa, bool perRow) {
  constexpr int32_t kRows = 12, kStride = 128;
  std::vector<uint32_t> id(kRows * kStride), s(kRows * kStride);
  std::mt19937 rng(4);
  for (auto& v : id) v = rng() % 4 == 0 ? 2u : 1u;
  std::vector<std::pair<int32_t, int32_t>> runs(kRows);
  for (int32_t y = 0; y < kRows; ++y) runs[size_t(y)] = {5 + 3 * y, 25 + 3 * y};
  raster::SpanPlanes p{};
  p.rgb[0] = {40u << 16, 3000u, 2000u};
  p.rgb[1] = {90u << 16, 0u - 1000u, 500u};
  p.rgb[2] = {10u << 16, 200u, 0u - 700u};
  std::vector<int32_t> begin(kRows, kStride), end(kRows, 0);
  const raster::SpanKernels& k = raster::spanKernelsFor(isa);
  for (auto _ : state) {
    if (perRow) {
      for (int32_t y = 0; y < kRows; ++y) {
        const size_t row = size_t(y) * kStride;
        benchmark::DoNotOptimize(k.interpolateS(&s[row], &id[row], runs[size_t(y)].first,
                                                runs[size_t(y)].second, y, p, 1));
      }
    } else {
      benchmark::DoNotOptimize(k.interpolateRuns(s.data(), id.data(), kStride, 0, kRows,
                                                 runs.data(), p, 1, begin.data(), end.data()));
    }
    benchmark::DoNotOptimize(s.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kRows * 20);
}

// Triangle setup (spec §4–5) of shadow-map-sized triangles, as every pass does for each
// occluder triangle, up to 12 texels wide: items are triangles; drawn_share is the share
// that covers a pixel centre (the rest are rejected by their bounding box or det = 0).
void BM_SetupTriangle(benchmark::State& state) {
  std::mt19937 rng(6);
  std::uniform_int_distribution<int32_t> corner(0, 250 * 256), offset(0, 12 * 256);
  std::uniform_real_distribution<float> z(0.0f, 1.0f);
  std::vector<std::array<raster::SnappedVertex, 3>> input(1024);
  for (auto& v : input) {
    const int32_t x0 = corner(rng), y0 = corner(rng);
    for (auto& p : v) {
      p.x = x0 + offset(rng);
      p.y = y0 + offset(rng);
      p.z = z(rng);
    }
  }
  raster::SetupTriangle t;
  int64_t drawn = 0;
  for (auto _ : state) {
    for (const auto& v : input) drawn += raster::setupTriangle(v, 256, 256, t) ? 1 : 0;
    benchmark::DoNotOptimize(t);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(input.size()));
  state.counters["drawn_share"] = double(drawn) / double(state.iterations()) / double(input.size());
}

raster::FrameTrace benchTrace() {
  const auto path = std::filesystem::path(PENUMBRA_DATA_DIR) / "traces" / "showroom-50.json";
  if (std::filesystem::exists(path)) return raster::loadTrace(path);
  testing::TestSceneOptions o;
  o.width = 640;
  o.height = 480;
  o.passes = 50;
  return testing::makeTestScene(o);
}

// A whole frame of the showroom trace (640x480, 50 passes); reports pass pixels/s.
void BM_Frame(benchmark::State& state, simd::Isa isa) {
  static const raster::FrameTrace trace = benchTrace();
  raster::Renderer r(trace.view, {isa, int(state.range(0)), 32});
  std::vector<uint8_t> out(trace.frame.background.size());
  for (auto _ : state) r.render(trace.frame, out);
  state.counters["pass_pixels"] = double(r.lastStats().passPixels);
  state.counters["map_pixels"] = double(r.lastStats().shadowMapPixels);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(r.lastStats().passPixels));
}

void registerAll() {
  benchmark::RegisterBenchmark("SetupTriangle", BM_SetupTriangle);
  for (simd::Isa isa : simd::supportedIsas()) {
    const std::string n = simd::isaName(isa);
    benchmark::RegisterBenchmark(("ProductU8/" + n).c_str(), BM_ProductU8, isa);
    benchmark::RegisterBenchmark(("DepthLess/" + n).c_str(), BM_DepthLess, isa);
    benchmark::RegisterBenchmark(("AccumulateRows/binary/" + n).c_str(), BM_AccumulateRows, isa,
                                 false);
    benchmark::RegisterBenchmark(("AccumulateRows/pcf2x2/" + n).c_str(), BM_AccumulateRows, isa,
                                 true);
    benchmark::RegisterBenchmark(("InterpolateRuns/per_row/" + n).c_str(), BM_InterpolateRuns, isa,
                                 true);
    benchmark::RegisterBenchmark(("InterpolateRuns/per_triangle/" + n).c_str(), BM_InterpolateRuns,
                                 isa, false);
    benchmark::RegisterBenchmark(("DepthTriangle/" + n).c_str(), BM_DepthTriangle, isa)
        ->Arg(4)
        ->Arg(8)
        ->Arg(16)
        ->Arg(48)
        ->Arg(160);
    benchmark::RegisterBenchmark(("Frame/" + n).c_str(), BM_Frame, isa)
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  penumbra::registerAll();
  return penumbra::bench::benchmarkMain("penumbra_bench", argc, argv);
}
