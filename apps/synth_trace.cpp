// penumbra-synth-trace: writes the synthetic frame traces the rasterizer is tested and
// benchmarked on (data/traces/README.md). The scenes and the pipeline that turns them into
// traces are shadow/synthetic_traces.h; this program picks them and writes the files.
// --random SEED --count N writes N random adversarial traces instead (raster/
// adversarial_trace.h), random-SEED.json up to random-(SEED+N-1).json.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <string>

#include "core/cli.h"
#include "raster/adversarial_trace.h"
#include "raster/frame_trace.h"
#include "shadow/synthetic_traces.h"

namespace {

namespace raster = penumbra::raster;
namespace shadow = penumbra::shadow;

void writeTrace(const raster::FrameTrace& trace, const std::filesystem::path& dir,
                const std::string& name, size_t receiverTriangles) {
  raster::validateTrace(trace, name);
  const std::filesystem::path json = dir / (name + ".json");
  raster::saveTrace(trace, json);
  const std::filesystem::path bin = dir / (name + ".bin");
  size_t objectTris = 0;
  for (const auto& o : trace.frame.objects) objectTris += o.mesh.triangleCount();
  std::cout << name << ": " << trace.view.width << "x" << trace.view.height << ", static "
            << trace.view.staticMesh.triangleCount() << " tris, object " << objectTris << " tris, "
            << trace.frame.passes.size() << " passes, " << receiverTriangles << " receiver tris, "
            << std::filesystem::file_size(json) << " + " << std::filesystem::file_size(bin)
            << " bytes\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Writes the synthetic frame traces (data/traces/README.md)."};
  std::string sceneName = "all";
  std::filesystem::path outDir = "data/traces";
  app.add_option("--scene", sceneName, "Which trace to write")
      ->check(CLI::IsMember(
          {"showroom", "tiny", "edges", "pcf", "showroom-720p", "showroom-1080p", "all"}))
      ->capture_default_str();
  app.add_option("-o,--out", outDir, "Output directory (created if missing)")
      ->capture_default_str();
  uint64_t randomSeed = 0;
  int count = 1;
  auto* random = app.add_option("--random", randomSeed,
                                "Write random adversarial traces from this seed instead "
                                "(clipping, far planes, maps' edges, negative bias, duplicates)");
  app.add_option("--count", count, "How many random traces (seeds SEED, SEED + 1, ...)")
      ->check(penumbra::cli::NumberRange(1, 100000))
      ->needs(random);
  return penumbra::cli::run("penumbra-synth-trace", app, argc, argv, [&] {
    std::filesystem::create_directories(outDir);
    if (random->count() > 0) {
      for (int k = 0; k < count; ++k) {
        const uint64_t seed = randomSeed + static_cast<uint64_t>(k);
        const raster::FrameTrace trace = raster::adversarialTrace(seed);
        size_t receivers = 0;
        for (const auto& pass : trace.frame.passes) receivers += pass.receiverTriangles.size();
        writeTrace(trace, outDir, "random-" + std::to_string(seed), receivers);
      }
      return 0;
    }
    for (const std::string& key : shadow::syntheticTraceKeys()) {
      if (sceneName != "all" && sceneName != key) continue;
      const shadow::SyntheticTrace t = shadow::synthesizeTrace(key);
      writeTrace(t.trace, outDir, t.name, t.receiverTriangles);
    }
    return 0;
  });
}
