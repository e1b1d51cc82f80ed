#include "apps/capture_command.h"

#ifdef PENUMBRA_HAVE_CAPTURE
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "core/cli.h"
#include "core/progress.h"
#include "lighting/capture.h"
#include "shadow/scene_bundle.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_CAPTURE
namespace {

struct CaptureFlags {
  std::string manifest, out;
  unsigned threads = 2;
};

int runCaptureCommand(const CaptureFlags& f) {
  const auto t0 = std::chrono::steady_clock::now();
  const lighting::CaptureManifest manifest = lighting::loadCaptureManifest(f.manifest);
  lighting::PrecomputeOptions options;
  options.threads = f.threads;
  lighting::CaptureResult r;
  core::Progress progress("capture");
  try {
    r = lighting::runCapture(manifest, options,
                             [&](const std::string& stage, int index, int count) {
                               progress.stage(stage, index, count);
                             });
  } catch (...) {
    progress.finish();
    throw;
  }
  shadow::saveBundle(r.bundle, f.out);
  const double totalMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  progress.finish();

  const lighting::CaptureSummary& s = r.summary;
  std::printf("calibration %s\n", s.calibrationMethod.c_str());
  std::printf("focal_px %.2f %.2f principal_point %.2f %.2f principal_offset_px %.2f\n",
              s.intrinsics.fx, s.intrinsics.fy, s.intrinsics.cx, s.intrinsics.cy,
              s.principalOffsetPx);
  const glm::dvec3 eye = s.pose.centre();
  std::printf("camera_centre %.4f %.4f %.4f\n", eye.x, eye.y, eye.z);
  std::printf("intrinsics_error_px %.4f\n", s.intrinsicsErrorPx);
  std::printf("reprojection_error_px %.4f\n", s.reprojectionErrorPx);
  std::printf("dynamic_range stops %.1f decades %.2f (clipped bright %zu dark %zu pixels)\n",
              s.dynamicRangeStops, s.dynamicRangeStops * std::log10(2.0), s.clippedBright,
              s.clippedDark);
  std::printf("live_exposure_s %g channel_to_grey %.4f %.4f %.4f\n", s.liveSeconds,
              s.channelToGrey.x, s.channelToGrey.y, s.channelToGrey.z);
  std::printf("probe_scale %.5g %.5g %.5g (fitted on %zu patches, spread %.1f%%)\n", s.probeScale.x,
              s.probeScale.y, s.probeScale.z, s.scalePatches, 100 * s.scaleSpread);
  std::printf("probe seen_patches %zu emitters %zu\n", s.probeSeenPatches, s.probeEmitters);
  std::printf("patches %zu sources %zu receivers %zu\n", s.patches, s.sources, s.receivers);
  for (const std::string& w : s.warnings) std::printf("warning %s\n", w.c_str());
  for (const lighting::StageTiming& t : s.timings) {
    std::printf("stage %-22s %9.1f ms\n", t.stage.c_str(), t.ms);
  }
  std::printf("total %.1f ms -> %s\n", totalMs, f.out.c_str());
  return 0;
}

}  // namespace
#endif

std::vector<Command> addCaptureCommands([[maybe_unused]] CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_CAPTURE
  auto flags = std::make_shared<CaptureFlags>();
  CLI::App* cmd = app.add_subcommand(
      "capture", "Photographs + marks + room JSON + light probe -> scene bundle (docs/capture.md)");
  cmd->add_option("MANIFEST", flags->manifest, "capture manifest (.json)")->required();
  cmd->add_option("-o,--out", flags->out, "bundle to write")->required();
  cmd->add_option("--threads", flags->threads, "threads")
      ->check(cli::NumberRange(1u, 256u))
      ->capture_default_str();
  commands.push_back({cmd, [flags] { return runCaptureCommand(*flags); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
