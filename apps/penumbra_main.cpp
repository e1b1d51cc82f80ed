// `penumbra`: the command-line front end. Subcommands:
//   replay TRACE        render one frame trace (docs/trace-format.md), write PNG / hash
//   isas                list compiled and supported SIMD targets
//   bench-replay TRACE  median and min ms per frame over repeated renders
//   precompute, render, profile   the showroom pipeline (apps/scene_commands.h)
//   calibrate           camera intrinsics and pose (apps/calibrate_command.h; with OpenCV)
//   compare A B         image metrics and FLIP (apps/compare_command.h; with OpenCV)
//   accuracy BUNDLE     ms and error against a reference per pass count (with OpenCV)
//   capture             photographs + probe -> scene bundle (apps/capture_command.h)
//   bench-envmap        live lighting's stages timed (apps/envmap_command.h)
//   envmap-sequence     a light probe animated into fisheye EXR frames (apps/envmap_command.h)
//   camera-response     an 8-bit bracket -> the environment camera's response file
//                       (apps/camera_response_command.h; with OpenCV)
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "apps/accuracy_command.h"
#include "apps/calibrate_command.h"
#include "apps/camera_response_command.h"
#include "apps/capture_command.h"
#include "apps/compare_command.h"
#include "apps/envmap_command.h"
#include "apps/reference_commands.h"
#include "apps/render_flags.h"
#include "apps/scene_commands.h"
#include "core/cli.h"
#include "raster/frame_trace.h"
#include "raster/renderer.h"
#include "scene/image_io.h"
#include "scene/sha256.h"
#include "simd/targets.h"

namespace {

using namespace penumbra;
using apps::addRenderFlags;
using apps::RenderFlags;
using apps::toOptions;

// Loads `tracePath`; a non-empty `accumulation` ("u8" / "fixed8_8", docs/pipeline-spec.md §8)
// replaces the trace's own (a linear trace's shade table is dropped: the other modes have
// none, and linear cannot be asked of a trace without one).
raster::FrameTrace loadTraceWith(const std::string& tracePath, const std::string& accumulation) {
  raster::FrameTrace trace = raster::loadTrace(tracePath);
  if (!accumulation.empty()) {
    trace.frame.accumulation = raster::parseAccumulation(accumulation, "--accumulation");
    trace.frame.shadeTable.clear();
  }
  return trace;
}

void addAccumulationFlag(CLI::App* app, std::string& accumulation) {
  app->add_option("--accumulation", accumulation,
                  "sum the passes as u8 (whole levels per pass) or fixed8_8 (1/256 levels, "
                  "rounded once per pixel); "
                  "default: the trace's field (which may also be linear)")
      ->check(CLI::IsMember({"u8", "fixed8_8"}));
}

int replay(const std::string& tracePath, const std::string& accumulation, const RenderFlags& flags,
           const std::string& outPath, bool printHash) {
  const raster::FrameTrace trace = loadTraceWith(tracePath, accumulation);
  const std::vector<uint8_t> rgba = raster::renderTrace(trace, toOptions(flags));
  if (!outPath.empty()) scene::writePng(outPath, trace.view.width, trace.view.height, rgba);
  if (printHash) std::cout << "sha256 " << scene::sha256Hex(rgba) << "\n";
  return 0;
}

// The first "cpu MHz" of /proc/cpuinfo (x86 Linux); 0 where it is not reported.
double nominalCpuHz() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (!line.starts_with("cpu MHz")) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) return 0;
    char* end = nullptr;
    const double mhz = std::strtod(line.c_str() + colon + 1, &end);
    return end == line.c_str() + colon + 1 ? 0 : mhz * 1e6;
  }
  return 0;
}

int benchReplay(const std::string& tracePath, const std::string& accumulation,
                const RenderFlags& flags, int frames) {
  const raster::FrameTrace trace = loadTraceWith(tracePath, accumulation);
  const raster::RenderOptions options = toOptions(flags);
  raster::Renderer renderer(trace.view, options);
  std::vector<uint8_t> rgba(size_t{trace.view.width} * trace.view.height * 4);
  renderer.render(trace.frame, rgba);  // warm-up: caches, page faults, thread start
  std::vector<double> ms, objectsMs, passesMs, finishMs;
  for (int f = 0; f < frames; ++f) {
    const auto start = std::chrono::steady_clock::now();
    renderer.render(trace.frame, rgba);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
    objectsMs.push_back(renderer.lastStats().msObjects);
    passesMs.push_back(renderer.lastStats().msPasses);
    finishMs.push_back(renderer.lastStats().msFinish);
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const raster::FrameStats& stats = renderer.lastStats();
  std::printf("trace %s\n", tracePath.c_str());
  std::printf("size %ux%u passes %zu isa %s threads %d tile %d frames %d accumulation %s\n",
              trace.view.width, trace.view.height, trace.frame.passes.size(),
              simd::isaName(options.isa), options.threads, options.tileSize, frames,
              raster::accumulationName(trace.frame.accumulation));
  std::printf("ms_per_frame median %.3f min %.3f\n", median(ms),
              *std::min_element(ms.begin(), ms.end()));
  std::printf("stage_ms_median objects %.3f passes %.3f finish %.3f\n", median(objectsMs),
              median(passesMs), median(finishMs));
  std::printf("pixels shadow_map %llu pass %llu object %llu\n",
              static_cast<unsigned long long>(stats.shadowMapPixels),
              static_cast<unsigned long long>(stats.passPixels),
              static_cast<unsigned long long>(stats.objectPixels));
  // Cycles per receiver pixel per pass, to project the cost to other CPUs: the whole pass
  // stage (shadow maps, S, masks) per matched receiver pixel, at the nominal clock, summed
  // over threads.
  const double hz = nominalCpuHz();
  if (hz > 0 && stats.passPixels > 0) {
    std::printf("pass_cycles_per_receiver_pixel %.2f (at %.0f MHz, %d threads)\n",
                median(passesMs) * 1e-3 * hz * options.threads / double(stats.passPixels),
                hz * 1e-6, options.threads);
  }
  std::printf("sha256 %s\n", scene::sha256Hex(rgba).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Penumbra: CPU-only, bit-exact soft shadows for augmented reality"};
  app.require_subcommand(1);

  RenderFlags replayFlags;
  std::string replayTrace, replayOut, replayAccumulation;
  bool replayHash = false;
  CLI::App* replayCmd = app.add_subcommand("replay", "Render one frame trace");
  replayCmd->add_option("TRACE", replayTrace, "frame trace (.json)")->required();
  addRenderFlags(replayCmd, replayFlags);
  replayCmd->add_option("--out", replayOut, "write the frame as PNG");
  replayCmd->add_flag("--hash", replayHash, "print `sha256 <hex>` of the RGBA8 frame bytes");
  addAccumulationFlag(replayCmd, replayAccumulation);

  app.add_subcommand("isas", "List SIMD targets: compiled, and whether this CPU runs them");

  RenderFlags benchFlags;
  benchFlags.threads = 2;
  std::string benchTrace, benchAccumulation;
  int benchFrames = 50;
  CLI::App* benchCmd = app.add_subcommand("bench-replay", "Time repeated renders of one trace");
  benchCmd->add_option("TRACE", benchTrace, "frame trace (.json)")->required();
  addRenderFlags(benchCmd, benchFlags);
  addAccumulationFlag(benchCmd, benchAccumulation);
  benchCmd->add_option("--frames", benchFrames, "timed frames")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();

  const std::vector<apps::Command> sceneCommands = apps::addSceneCommands(app);
  const std::vector<apps::Command> calibrateCommands = apps::addCalibrateCommands(app);
  const std::vector<apps::Command> compareCommands = apps::addCompareCommands(app);
  const std::vector<apps::Command> accuracyCommands = apps::addAccuracyCommands(app);
  const std::vector<apps::Command> captureCommands = apps::addCaptureCommands(app);
  const std::vector<apps::Command> referenceCommands = apps::addReferenceCommands(app);
  const std::vector<apps::Command> envmapCommands = apps::addEnvmapCommands(app);
  const std::vector<apps::Command> responseCommands = apps::addCameraResponseCommands(app);

  return cli::run("penumbra", app, argc, argv, [&] {
    for (const apps::Command& c : sceneCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : calibrateCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : compareCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : accuracyCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : captureCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : referenceCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : envmapCommands) {
      if (c.app->parsed()) return c.run();
    }
    for (const apps::Command& c : responseCommands) {
      if (c.app->parsed()) return c.run();
    }
    if (replayCmd->parsed()) {
      return replay(replayTrace, replayAccumulation, replayFlags, replayOut, replayHash);
    }
    if (benchCmd->parsed())
      return benchReplay(benchTrace, benchAccumulation, benchFlags, benchFrames);
    for (simd::Isa isa : simd::compiledIsas()) {
      std::cout << simd::isaName(isa)
                << (simd::isSupported(isa) ? "" : " (not supported by this CPU)") << "\n";
    }
    return 0;
  });
}
