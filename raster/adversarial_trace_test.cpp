#include "raster/adversarial_trace.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/scratch_dir.h"

namespace penumbra::raster {
namespace {

std::vector<char> fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(AdversarialTrace, SameSeedSameBytes) {
  const std::filesystem::path dir = test::scratchPath("adversarial");
  std::filesystem::create_directories(dir);
  for (const uint64_t seed : {1ull, 7ull, 123456789ull}) {
    const std::filesystem::path a = dir / ("a" + std::to_string(seed) + ".json");
    const std::filesystem::path b = dir / ("b" + std::to_string(seed) + ".json");
    saveTrace(adversarialTrace(seed), a);
    saveTrace(adversarialTrace(seed), b);
    const std::vector<char> binA = fileBytes(std::filesystem::path(a).replace_extension(".bin"));
    EXPECT_FALSE(binA.empty());
    EXPECT_EQ(binA, fileBytes(std::filesystem::path(b).replace_extension(".bin"))) << seed;
    // The JSON names its own sidecar; everything else must match.
    const FrameTrace loadedA = loadTrace(a), loadedB = loadTrace(b);
    EXPECT_EQ(loadedA, loadedB) << seed;
    EXPECT_EQ(loadedA, adversarialTrace(seed)) << "round trip of seed " << seed;
  }
  EXPECT_FALSE(adversarialTrace(1) == adversarialTrace(2));
  std::filesystem::remove_all(dir);
}

TEST(AdversarialTrace, EverySeedShowsTheFeatures) {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE(seed);
    const FrameTrace trace = adversarialTrace(seed);
    EXPECT_EQ(trace.frame.accumulation, Accumulation::kU8);
    const AdversarialFeatures f = adversarialFeatures(trace);
    EXPECT_GT(f.behindEye, 0u);
    EXPECT_GT(f.outsideLightMap, 0u);
    EXPECT_GT(f.duplicatePairs, 0u);
  }
  // Per-pass features are drawn per pass: over a dozen seeds each appears many times.
  AdversarialFeatures all;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const AdversarialFeatures f = adversarialFeatures(adversarialTrace(seed));
    all.beyondLightFar += f.beyondLightFar;
    all.negativeBiasPasses += f.negativeBiasPasses;
    all.pcfPasses += f.pcfPasses;
    all.objectReceiverPasses += f.objectReceiverPasses;
  }
  EXPECT_GT(all.beyondLightFar, 12u);
  EXPECT_GT(all.negativeBiasPasses, 6u);
  EXPECT_GT(all.pcfPasses, 6u);
  EXPECT_GT(all.objectReceiverPasses, 6u);
}

}  // namespace
}  // namespace penumbra::raster
