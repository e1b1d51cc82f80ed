// `penumbra-capture-synth SCENE DIR`: writes a capture with a known answer (brackets, a
// lat-long probe, vanishing marks, capture.json) for `penumbra capture`
// (lighting/capture_synth.h, docs/capture.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "core/cli.h"
#include "lighting/capture_synth.h"

int main(int argc, char** argv) {
  CLI::App app{"Synthetic photographs, probe and marks of a scene file's room"};
  std::string scenePath, dir;
  app.add_option("SCENE", scenePath, "scene file (the truth)")->required();
  app.add_option("DIR", dir, "output folder")->required();
  std::vector<double> gains;
  app.add_option("--gains", gains, "the synthetic camera's channel gains R,G,B (default 1,0.8,1.2)")
      ->expected(3)
      ->delimiter(',');
  std::vector<double> offset;
  bool chessboard = false;
  app.add_option("--principal-offset", offset, "principal point offset DX,DY from the centre (px)")
      ->expected(2)
      ->delimiter(',');
  app.add_flag("--chessboard", chessboard,
               "calibrate from chessboard photos and room corners instead of vanishing marks");
  return penumbra::cli::run("penumbra-capture-synth", app, argc, argv, [&] {
    penumbra::lighting::SyntheticCaptureOptions options;
    if (!gains.empty()) options.gains = {gains[0], gains[1], gains[2]};
    if (!offset.empty()) options.principalOffsetPx = {offset[0], offset[1]};
    options.chessboard = chessboard;
    const penumbra::lighting::SyntheticCapture c =
        penumbra::lighting::writeSyntheticCapture(scenePath, dir, options);
    std::printf("manifest %s\nfocal_px %.3f\nprobe_scale %.5g %.5g %.5g\n",
                c.manifest.string().c_str(), c.intrinsics.fx, c.probeScale.x, c.probeScale.y,
                c.probeScale.z);
    return 0;
  });
}
