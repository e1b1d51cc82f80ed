// `penumbra-capture-synth SCENE DIR`: writes a capture with a known answer (brackets, a
// lat-long probe, vanishing marks, capture.json) for `penumbra capture`
// (lighting/capture_synth.h, docs/capture.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "lighting/capture_synth.h"

int main(int argc, char** argv) {
  CLI::App app{"Synthetic photographs, probe and marks of a scene file's room"};
  std::string scenePath, dir;
  app.add_option("SCENE", scenePath, "scene file (the truth)")->required();
  app.add_option("DIR", dir, "output folder")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    const penumbra::lighting::SyntheticCapture c =
        penumbra::lighting::writeSyntheticCapture(scenePath, dir);
    std::printf("manifest %s\nfocal_px %.3f\nprobe_scale %.5g %.5g %.5g\n",
                c.manifest.string().c_str(), c.intrinsics.fx, c.probeScale.x, c.probeScale.y,
                c.probeScale.z);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra-capture-synth: error: %s\n", e.what());
    return 1;
  }
}
