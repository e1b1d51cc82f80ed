// The bit-exact contract (docs/pipeline-spec.md): every supported SIMD target x threads
// {1,2,3,4,8} x tiles {16,32,64} renders every trace to the same bytes, and the bundled
// traces render to their golden hashes (tests/golden_hashes.txt).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "raster/renderer.h"
#include "scene/sha256.h"
#include "tests/test_scenes.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> bundledTraces() {
  std::vector<fs::path> out;
  const fs::path dir = fs::path(PENUMBRA_DATA_DIR) / "traces";
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".json") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::map<std::string, std::string> goldenHashes() {
  std::map<std::string, std::string> out;
  std::ifstream in(fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "golden_hashes.txt");
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

void expectInvariant(const raster::FrameTrace& trace, const std::string& name) {
  const std::string reference = hashOf(trace, {simd::Isa::kScalar, 1, 32});
  for (simd::Isa isa : simd::supportedIsas()) {
    for (int threads : {1, 2, 3, 4, 8}) {
      for (int tile : {16, 32, 64}) {
        EXPECT_EQ(hashOf(trace, {isa, threads, tile}), reference)
            << name << ": isa " << simd::isaName(isa) << " threads " << threads << " tile " << tile;
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

// Fixed-point accumulation (spec §8) with PCF masks, where its rounding differs from u8's.
TEST(Invariance, GeneratedSceneWithFixedPointAccumulation) {
  testing::TestSceneOptions o;
  o.pcf2x2 = true;
  o.width = 150;
  o.height = 97;
  raster::FrameTrace trace = testing::makeTestScene(o);
  trace.frame.accumulation = raster::Accumulation::kFixed8_8;
  expectInvariant(trace, "generated pcf fixed8_8");
}

TEST(Invariance, BundledTraces) {
  for (const fs::path& path : bundledTraces()) {
    expectInvariant(raster::loadTrace(path), path.filename().string());
  }
}

TEST(Golden, BundledTracesMatchTheirHashes) {
  const auto golden = goldenHashes();
  const auto traces = bundledTraces();
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
