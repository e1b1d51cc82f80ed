// The bit-exact contract (docs/pipeline-spec.md): every supported SIMD target x threads
// {1,2,3,4,8} x tiles {16,32,64} renders every trace to the same bytes, and the bundled
// traces render to their golden hashes (tests/golden_hashes.txt).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "raster/renderer.h"
#include "scene/sha256.h"
#include "tests/test_scenes.h"
#include "tests/test_workload.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// The committed traces of data/traces. They are part of the repository, so an empty or
// missing folder is a broken checkout, not a reason to check nothing: the caller asserts.
std::vector<fs::path> bundledTraces() {
  std::vector<fs::path> out;
  const fs::path dir = fs::path(PENUMBRA_DATA_DIR) / "traces";
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".json") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

const char* const kNoTraces = "no frame traces in " PENUMBRA_DATA_DIR
                              "/traces: the committed data/traces/*.json are "
                              "missing (a partial checkout?); these tests would check nothing";

std::map<std::string, std::string> goldenHashes() {
  std::map<std::string, std::string> out;
  std::ifstream in(fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "golden_hashes.txt");
  if (!in) throw std::runtime_error(PENUMBRA_SOURCE_DIR "/tests/golden_hashes.txt: cannot read");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string name, hash;
    fields >> name >> hash;
    out[name] = hash;
  }
  return out;
}

std::string hashOf(const raster::FrameTrace& trace, const raster::RenderOptions& options) {
  return scene::sha256Hex(raster::renderTrace(trace, options));
}

// Frames of more pixels than the 640x480 benchmark (the 720p and 1080p showroom traces) take
// no other code path, only more tiles and larger coordinates: each target renders them at a
// fifth of the grid, three points spaced so that the targets together meet every thread count
// and tile size (one point per target under the small workload).
bool sparseGrid(const raster::FrameTrace& trace) {
  return size_t{trace.view.width} * trace.view.height > size_t{640} * 480;
}

void expectInvariant(const raster::FrameTrace& trace, const std::string& name) {
  const std::string reference = hashOf(trace, {simd::Isa::kScalar, 1, 32});
  // Under the small workload (tests/test_workload.h) every target renders at every thread count
  // with one tile size each (the sizes rotate, so every target meets every size and every
  // thread count meets every size across the targets): a third of the grid.
  const bool small = testing::smallTestWorkload(), sparse = sparseGrid(trace);
  const std::vector<simd::Isa> isas = simd::supportedIsas();
  const int threadCounts[] = {1, 2, 3, 4, 8};
  const int tiles[] = {16, 32, 64};
  for (size_t i = 0; i < isas.size(); ++i) {
    for (size_t t = 0; t < std::size(threadCounts); ++t) {
      for (size_t k = 0; k < std::size(tiles); ++k) {
        const size_t point = t * std::size(tiles) + k;  // 0..14
        if (sparse && small && point != (7 * i) % 15) continue;
        if (sparse && !small && point % 5 != i % 5) continue;
        if (!sparse && small && k != (i + t) % std::size(tiles)) continue;
        const int threads = threadCounts[t], tile = tiles[k];
        EXPECT_EQ(hashOf(trace, {isas[i], threads, tile}), reference)
            << name << ": isa " << simd::isaName(isas[i]) << " threads " << threads << " tile "
            << tile;
      }
    }
  }
}

TEST(Invariance, GeneratedScenes) {
  for (bool pcf : {false, true}) {
    testing::TestSceneOptions o;
    o.pcf2x2 = pcf;
    o.width = 150;  // not a multiple of any tile size or vector width
    o.height = 97;
    expectInvariant(testing::makeTestScene(o), pcf ? "generated pcf" : "generated");
  }
}

// Fixed-point and linear accumulation (spec §8) with PCF masks and S with fractions of a
// level (8.8, spec §5), where their rounding differs from u8's.
TEST(Invariance, GeneratedSceneWithFixedPointAndLinearAccumulation) {
  testing::TestSceneOptions o;
  o.pcf2x2 = true;
  o.width = 150;
  o.height = 97;
  raster::FrameTrace trace = testing::makeTestScene(o);
  trace.frame.accumulation = raster::Accumulation::kFixed8_8;
  uint32_t fraction = 0;
  for (raster::ShadowPass& pass : trace.frame.passes) {
    for (auto* list : {&pass.receiverS, &pass.objectS}) {
      for (core::Rgb16& s : *list) {
        for (uint16_t* c : {&s.r, &s.g, &s.b}) {
          fraction = (fraction * 1103515245u + 12345u) & 0x7FFFFFFFu;
          if (*c != 0 && *c < core::kMaxFineLevel)
            *c = static_cast<uint16_t>(*c + (fraction >> 23));
        }
      }
    }
  }
  expectInvariant(trace, "generated pcf fixed8_8");
  trace.frame.accumulation = raster::Accumulation::kLinear;
  // A linear camera response's table (shadow::linearShadeTable builds a real one): the
  // pixel's code scaled by the unoccluded share, rounded half up.
  trace.frame.shadeTable.resize(raster::kShadeCodes * raster::kShadeSteps);
  for (size_t c = 0; c < raster::kShadeCodes; ++c) {
    for (size_t q = 0; q < raster::kShadeSteps; ++q) {
      trace.frame.shadeTable[c * raster::kShadeSteps + q] =
          static_cast<uint8_t>((c * (raster::kShadeSteps - 1 - q) * 2 + 510) / 1020);
    }
  }
  expectInvariant(trace, "generated pcf linear");
}

TEST(Invariance, BundledTraces) {
  const auto traces = bundledTraces();
  ASSERT_FALSE(traces.empty()) << kNoTraces;
  for (const fs::path& path : traces) {
    expectInvariant(raster::loadTrace(path), path.filename().string());
  }
}

TEST(Golden, BundledTracesMatchTheirHashes) {
  const auto golden = goldenHashes();
  const auto traces = bundledTraces();
  ASSERT_FALSE(traces.empty()) << kNoTraces;
  ASSERT_FALSE(golden.empty()) << "tests/golden_hashes.txt lists no hashes";
  for (const fs::path& path : traces) {
    const std::string name = path.filename().string();
    const auto it = golden.find(name);
    ASSERT_NE(it, golden.end()) << name << " has no golden hash in tests/golden_hashes.txt";
    EXPECT_EQ(hashOf(raster::loadTrace(path), {simd::bestIsa(), 2, 32}), it->second) << name;
  }
  EXPECT_EQ(golden.size(), traces.size()) << "golden_hashes.txt lists traces that do not exist";
}

}  // namespace
}  // namespace penumbra
