#include "apps/envmap_command.h"

#include <cstdio>
#include <memory>

#include "core/cli.h"
#ifdef PENUMBRA_HAVE_ENVMAP_BENCH
#include "envmap/envmap_benchmark.h"
#endif
#ifdef PENUMBRA_HAVE_ENVMAP_SEQUENCE
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

#include "core/error.h"
#include "envmap/fisheye_resampler.h"
#include "envmap/lat_long.h"
#include "envmap/probe_sequences.h"
#include "lighting/exr_io.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_ENVMAP_BENCH
namespace {

struct EnvmapBenchFlags {
  uint32_t lights = 300, frames = 200, clusters = 72, taps = 2;
};

int runEnvmapBench(const EnvmapBenchFlags& flags) {
  const envmap::EnvmapBenchResult r =
      envmap::benchEnvmap(flags.lights, flags.frames, flags.clusters, flags.taps);
  std::printf("map 360x90 lights %u frames %u clusters_max %u clusters_made %u threads 1\n",
              r.lights, r.frames, r.clusters, r.clustersMade);
  std::printf(
      "resample_ms %.4f (fisheye 480x480 -> map, %ux%u taps, frame not cached; in cdf_ms)\n",
      r.resampleMs, r.supersample, r.supersample);
  std::printf("resample_warm_ms %.4f (the same, frame already in the cache)\n", r.resampleWarmMs);
  std::printf("cdf_ms %.4f\n", r.cdfMs);
  std::printf("samples_per_ms %.0f\n", r.samplesPerMs);
  std::printf("filter_cluster_ms %.4f\n", r.filterClusterMs);
  return 0;
}

}  // namespace

#ifdef PENUMBRA_HAVE_ENVMAP_SEQUENCE
namespace {

namespace fs = std::filesystem;

struct EnvmapSequenceFlags {
  std::string probe, out;
  uint32_t frames = 48, size = 160;
  std::vector<std::string> animate;
};

// The animations by name, their parameters chosen so that each is plain to see in a loop of
// `frames` at the virtual camera's 21 Hz (envmap/probe_sequences.h has the models):
//   rotate    one full turn per loop (so the loop is seamless)
//   cloud     over the brightest region from frame F/8 for F/3 frames, 80% deep at its middle
//   lamp-off  the brightest region down to 2% from frame 2F/3 to the end of the loop
//   noise     ±2% uniform per sample (sensor noise)
//   flicker   ±10% at 100 Hz, seen at 21 Hz (aliased to 5 Hz: docs/live-lighting.md)
//   still     none of them (alone)
envmap::ProbeAnimation animationFor(const std::vector<std::string>& names, uint32_t frames) {
  envmap::ProbeAnimation a;
  const bool still = std::find(names.begin(), names.end(), "still") != names.end();
  if (still && names.size() > 1)
    throw cli::UsageError("--animate: 'still' cannot be combined with other animations");
  for (const std::string& name : names) {
    if (name == "rotate") {
      a.degreesPerFrame = 360.0 / frames;
    } else if (name == "cloud") {
      a.cloudFrom = frames / 8;
      a.cloudTo = a.cloudFrom + std::max<int64_t>(2, frames / 3);
    } else if (name == "lamp-off") {
      a.lampOffFrame = 2 * int64_t(frames) / 3;
    } else if (name == "noise") {
      a.noise = 0.02;
    } else if (name == "flicker") {
      a.flickerDepth = 0.1;
    } else if (name != "still") {
      throw cli::UsageError("--animate: unknown animation '" + name +
                            "' (lamp-off, cloud, noise, flicker, rotate, still)");
    }
  }
  return a;
}

// The probe averaged down to about the fisheye's own resolution (its horizon circle is π·size
// pixels round): a 160-pixel image point-sampling a 1024-pixel-wide probe would alias. The
// largest factor ≤ width / (π·size) that divides both sides.
uint32_t shrinkFactor(const core::ImageF& probe, uint32_t size) {
  uint32_t factor = std::max<uint32_t>(1, uint32_t(probe.width / (3.14159265358979323846 * size)));
  while (factor > 1 && (probe.width % factor != 0 || probe.height % factor != 0)) --factor;
  return factor;
}

int runEnvmapSequence(const EnvmapSequenceFlags& flags) {
  fs::path out = fs::path(flags.out).lexically_normal();
  if (!out.has_filename()) out = out.parent_path();  // "DIR/": the folder itself
  if (out.empty() || out == "." || out == "..")
    throw cli::UsageError("-o: '" + flags.out + "' is not a folder to create");
  std::error_code ec;
  if (fs::exists(out, ec) && (!fs::is_directory(out, ec) || !fs::is_empty(out, ec)))
    throw core::Error(flags.out, "", "exists and is not an empty folder (nothing written)");
  const envmap::ProbeAnimation animation = animationFor(flags.animate, flags.frames);

  lighting::ExrReadReport report;
  core::ImageF probe = lighting::readExr(flags.probe, &report);
  if (probe.width != 2 * probe.height || probe.height < 2)
    throw core::Error(flags.probe, "",
                      std::to_string(probe.width) + "x" + std::to_string(probe.height) +
                          " is not a lat-long probe (width = 2 × height)");
  const uint32_t factor = shrinkFactor(probe, flags.size);
  if (factor > 1) probe = envmap::shrinkLatLong(probe, factor);
  const envmap::FisheyeLens lens = envmap::FisheyeLens::equidistant180(flags.size);

  // Written beside the destination and renamed at the end: an interrupted or failed run
  // leaves no partial sequence under the name a camera or a test would load.
  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  fs::create_directories(parent);
  const fs::path tmp =
      parent / ("." + out.filename().string() + ".partial-" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directory(tmp);
  uintmax_t bytes = 0;
  try {
    for (uint32_t k = 0; k < flags.frames; ++k) {
      const core::ImageF frame =
          envmap::renderFisheye(envmap::animateProbe(probe, animation, k), lens);
      char name[32];
      std::snprintf(name, sizeof name, "env_%04u.exr", k);
      lighting::writeExr(tmp / name, frame, lighting::ExrPixels::Half);
      bytes += fs::file_size(tmp / name);
    }
    if (fs::exists(out)) fs::remove(out);  // empty (checked above)
    fs::rename(tmp, out);
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  std::printf("probe %s %ux%u (averaged %ux%u from %ux%u), %zu negative samples set to 0\n",
              flags.probe.c_str(), probe.width, probe.height, factor, factor, probe.width * factor,
              probe.height * factor, report.clampedNegative);
  std::printf(
      "wrote %u frames of %ux%u (equidistant 180° fisheye, half float, ZIP) to %s: "
      "%ju bytes\n",
      flags.frames, flags.size, flags.size, flags.out.c_str(), bytes);
  return 0;
}

}  // namespace
#endif

std::vector<Command> addEnvmapCommands(CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_ENVMAP_SEQUENCE
  auto sequence = std::make_shared<EnvmapSequenceFlags>();
  CLI::App* seq = app.add_subcommand(
      "envmap-sequence",
      "Animate a lat-long light probe and photograph it through a 180° fisheye: an EXR "
      "sequence for the environment camera (env_0000.exr ...)");
  seq->add_option("PROBE", sequence->probe, "lat-long light probe (.exr)")->required();
  seq->add_option("-o,--out", sequence->out, "new folder for the frames (absent or empty)")
      ->required();
  seq->add_option("--frames", sequence->frames, "frames (21 Hz)")
      ->check(cli::NumberRange(1, 10000))
      ->capture_default_str();
  seq->add_option("--size", sequence->size, "fisheye image size in pixels (square)")
      ->check(cli::NumberRange(16, 4096))
      ->capture_default_str();
  seq->add_option("--animate", sequence->animate,
                  "lamp-off, cloud, noise, flicker, rotate or still (several allowed)")
      ->expected(1, 6);
  commands.push_back({seq, [sequence] { return runEnvmapSequence(*sequence); }});
#endif
  auto flags = std::make_shared<EnvmapBenchFlags>();
  CLI::App* cmd = app.add_subcommand(
      "bench-envmap", "Time live lighting's stages: CDF, sampling, FIR + clustering (medians)");
  cmd->add_option("--lights", flags->lights, "lights sampled per frame")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  cmd->add_option("--frames", flags->frames, "timed frames")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  cmd->add_option("--taps", flags->taps, "fisheye resampling: N x N taps per map pixel")
      ->check(cli::NumberRange(1, 8))
      ->capture_default_str();
  cmd->add_option("--clusters", flags->clusters, "at most this many clusters (Q)")
      ->check(cli::NumberRange(1, 100000))
      ->capture_default_str();
  commands.push_back({cmd, [flags] { return runEnvmapBench(*flags); }});
  return commands;
}
#else
std::vector<Command> addEnvmapCommands(CLI::App&) {
  return {};
}
#endif

}  // namespace penumbra::apps
