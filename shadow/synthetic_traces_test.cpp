// The synthesis reproduces the committed traces: the binary sidecar of every quick trace
// (all but the showroom, seconds of ray casting) is byte for byte data/traces', so the
// data can be regenerated from this code. (The JSON halves are not compared: the committed
// ones predate the "accumulation" field the writer adds today.)
#include "shadow/synthetic_traces.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "tests/scratch_dir.h"

namespace penumbra::shadow {
namespace {

std::vector<char> bytesOf(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(SyntheticTraces, QuickTracesEqualTheCommittedData) {
  const std::filesystem::path dir = test::scratchPath("synth");
  std::filesystem::create_directories(dir);
  const std::filesystem::path data = std::filesystem::path(PENUMBRA_DATA_DIR) / "traces";
  for (const std::string key : {"tiny", "pcf", "edges"}) {
    const SyntheticTrace t = synthesizeTrace(key);
    EXPECT_EQ(t.name, key);
    EXPECT_GT(t.receiverTriangles, 0u);
    raster::validateTrace(t.trace, key);
    raster::saveTrace(t.trace, dir / (key + ".json"));
    const std::vector<char> made = bytesOf(dir / (key + ".bin"));
    ASSERT_FALSE(made.empty());
    EXPECT_TRUE(made == bytesOf(data / (key + ".bin"))) << key;
  }
  std::filesystem::remove_all(dir);
}

TEST(SyntheticTraces, KeysAndUnknownKey) {
  EXPECT_EQ(syntheticTraceKeys(), (std::vector<std::string>{"tiny", "pcf", "showroom", "edges",
                                                            "showroom-720p", "showroom-1080p"}));
  EXPECT_THROW(synthesizeTrace("nonesuch"), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
