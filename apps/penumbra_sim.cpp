// `penumbra-sim SESSION.json`: a whole kiosk session on the simulated board (issue 6 §5,
// docs/kiosk.md). The kiosk loop of platform/ runs with the simulated camera, buttons and
// LED of firmware-sim/, on a virtual clock advanced by the board's cost model, so every
// displayed frame — HUD included — is a pure function of the session: `--hashes` writes one
// `sha256 <64 hex>` line per frame (of the displayed RGBA8 frame, HUD included), the same
// for any --threads, --isa or machine.
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "apps/render_flags.h"
#include "core/cli.h"
#include "core/process_memory.h"
#include "core/replace_file.h"
#include "firmware-sim/frame_time_drift.h"
#include "firmware-sim/session.h"
#include "firmware-sim/session_stats.h"
#include "firmware-sim/sim_run.h"
#include "firmware-sim/soak.h"
#include "scene/image_io.h"
#include "scene/sha256.h"
#include "shadow/frame_stages.h"
#ifdef PENUMBRA_HAVE_OPENCV
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "apps/video_out.h"
#endif

using namespace penumbra;
using firmware_sim::percentile;

namespace {

double ms(int64_t ns) {
  return static_cast<double>(ns) * 1e-6;
}

// A strip of `count` frames side by side in two rows, each reduced 4× by a 4×4 box average
// (integers), for README/docs pictures without a video player.
class Strip {
 public:
  Strip(uint32_t w, uint32_t h, uint32_t count)
      : tw_(w / 4),
        th_(h / 4),
        cols_((count + 1) / 2),
        pixels_(size_t{tw_} * cols_ * th_ * 2 * 4) {}
  void add(const std::vector<uint8_t>& rgba, uint32_t w, uint32_t slot) {
    const uint32_t ox = (slot % cols_) * tw_, oy = (slot / cols_) * th_;
    const uint32_t stride = tw_ * cols_;
    for (uint32_t y = 0; y < th_; ++y) {
      for (uint32_t x = 0; x < tw_; ++x) {
        for (uint32_t c = 0; c < 4; ++c) {
          uint32_t sum = 0;
          for (uint32_t dy = 0; dy < 4; ++dy) {
            for (uint32_t dx = 0; dx < 4; ++dx) {
              sum += rgba[((size_t{y} * 4 + dy) * w + x * 4 + dx) * 4 + c];
            }
          }
          pixels_[((size_t{oy} + y) * stride + ox + x) * 4 + c] =
              static_cast<uint8_t>((sum + 8) / 16);
        }
      }
    }
  }
  void write(const std::string& path) const {
    scene::writePng(path, tw_ * cols_, th_ * 2, pixels_);
  }

 private:
  uint32_t tw_, th_, cols_;
  std::vector<uint8_t> pixels_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"penumbra-sim: replay a kiosk session on the simulated board (docs/kiosk.md)"};
  std::string sessionPath, hashesPath, videoPath, framesDir, stripPath, benchCsvPath;
  uint32_t frames = 0, stripCount = 6, soakFrames = 0;
  bool bench = false, echoLog = false;
  apps::RenderFlags flags;
  app.add_option("SESSION", sessionPath, "session file (.json)")->required();
  app.add_option("--frames", frames, "frames to run (default: the session's)")
      ->check(cli::NumberRange(1, 1'000'000));
  apps::addRenderFlags(&app, flags);
  app.add_option("--hashes", hashesPath, "write `sha256 <hex>` of each displayed frame");
#ifdef PENUMBRA_HAVE_OPENCV
  auto* video = app.add_option("--video", videoPath, "write an MP4 video (OpenCV VideoWriter)");
#else
  auto* video = app.add_option("--video", videoPath, "MP4 video: not in this build (no OpenCV)");
#endif
  auto* dir = app.add_option("--frames-dir", framesDir, "write every frame as DIR/frame-NNNN.png");
  video->excludes(dir);
  app.add_option("--strip", stripPath, "write a PNG strip of evenly spaced frames");
  app.add_option("--strip-frames", stripCount, "frames in the strip")
      ->check(cli::NumberRange(2, 12));
  auto* benchFlag =
      app.add_flag("--bench", bench, "time the loop on this machine (wall clock; not the board)");
  app.add_option("--bench-csv", benchCsvPath,
                 "with --bench: write every frame's stage times (ms) as CSV")
      ->needs(benchFlag);
  app.add_flag("--log", echoLog, "echo the kiosk log to stderr");
  app.add_option("--soak", soakFrames,
                 "soak: N frames of generated presses, camera faults and load steps on top of "
                 "SESSION (docs/kiosk.md, Soak); prints memory and frame-time drift")
      ->check(cli::NumberRange(1, 10'000'000));
  return cli::run("penumbra-sim", app, argc, argv, [&] {
    const firmware_sim::Session session =
        soakFrames != 0
            ? firmware_sim::soakSession(firmware_sim::loadSession(sessionPath), soakFrames)
            : firmware_sim::loadSession(sessionPath);
    const uint32_t n = frames ? frames : session.frames;
    firmware_sim::SimOptions options;
    options.render = apps::toOptions(flags);
    options.logEcho = echoLog ? stderr : nullptr;

    // The hashes go to a temporary file beside the target, renamed over it only when the
    // whole run succeeded: a failed run leaves no partial (or empty) hash file behind.
    std::ofstream hashes;
    std::string hashesTemp;
    if (!hashesPath.empty()) {
      // A device or pipe (/dev/null, /dev/stdout) is written as it is: nothing to rename.
      const bool special =
          std::filesystem::exists(hashesPath) && !std::filesystem::is_regular_file(hashesPath);
      if (!special) hashesTemp = hashesPath + ".tmp-" + std::to_string(::getpid());
      hashes.open(special ? hashesPath : hashesTemp);
      if (!hashes) throw std::runtime_error(hashesPath + ": cannot write");
    }
    struct RemoveTemp {
      const std::string& path;
      ~RemoveTemp() {
        if (!path.empty()) {
          std::error_code ignored;
          std::filesystem::remove(path, ignored);
        }
      }
    } removeTemp{hashesTemp};
    if (!framesDir.empty()) std::filesystem::create_directories(framesDir);
#ifdef PENUMBRA_HAVE_OPENCV
    cv::VideoWriter writer;
#else
    if (!videoPath.empty()) {
      throw cli::UsageError(
          "--video needs a build with OpenCV (PENUMBRA_WITH_OPENCV); "
          "use --frames-dir or --strip");
    }
#endif

    firmware_sim::SimRun run(session, options);
    const uint32_t w = run.width(), h = run.height();
#ifdef PENUMBRA_HAVE_OPENCV
    if (!videoPath.empty()) {
      const double fps = 1e9 / static_cast<double>(session.kiosk.fastFrameNs);
      writer = apps::openMp4(videoPath, fps, cv::Size(static_cast<int>(w), static_cast<int>(h)));
    }
#endif
    std::unique_ptr<Strip> strip;
    if (!stripPath.empty()) strip = std::make_unique<Strip>(w, h, stripCount);

    // Per-frame statistics, allocated and touched before the first frame, so that the
    // process's memory after warm-up is the kiosk's alone (the soak's RSS check).
    std::vector<int64_t> wallNs(n, 0);
    std::vector<uint32_t> passes(n, 0);
    firmware_sim::SessionStats stats(n);
    shadow::FrameStageSamples stageSamples;
    stageSamples.reserve(n);
    // The soak's drift: its first frames are replayed after the last (frame_time_drift.h).
    const uint32_t warmUpFrame = std::min<uint32_t>(n, 1000);
    const uint32_t driftFrames = soakFrames != 0 ? std::min<uint32_t>(n, 2 * warmUpFrame) : 0;
    firmware_sim::FrameTimeDrift drift(driftFrames);
    // Sampled inside the frame loop: after it, the run's statistics (sorted copies of every
    // frame's samples) would count as the kiosk's growth.
    core::ProcessMemory atWarmUp, atLastFrame;
    uint32_t degraded = 0, stale = 0, attract = 0;
    int64_t firstStart = 0, lastEnd = 0;
    for (uint32_t f = 0; f < n; ++f) {
      const auto t0 = std::chrono::steady_clock::now();
      const kiosk::FrameReport r = run.step();
      wallNs[f] = std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::steady_clock::now() - t0)
                      .count();
      if (f == 0) firstStart = r.startNs;
      lastEnd = r.endNs;
      stats.add(r);
      stageSamples.add(r.stages);
      passes[f] = r.passes;
      degraded += r.led != kiosk::LedState::kReady;
      stale += r.stale;
      attract += r.attract;
      const std::vector<uint8_t>& rgba = run.frame();
      // One digest a frame serves both the hash file and the soak's replay check.
      if (hashes || !drift.full()) {
        const std::array<uint8_t, 32> digest = scene::sha256(rgba);
        drift.add(r, digest);
        if (hashes) hashes << "sha256 " << scene::toHex(digest) << "\n";
      }
      if (!framesDir.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "frame-%04u.png", f + 1);
        scene::writePng(std::filesystem::path(framesDir) / name, w, h, rgba);
      }
#ifdef PENUMBRA_HAVE_OPENCV
      if (writer.isOpened()) {
        cv::Mat in(static_cast<int>(h), static_cast<int>(w), CV_8UC4,
                   const_cast<uint8_t*>(rgba.data()));
        cv::Mat bgr;
        cv::cvtColor(in, bgr, cv::COLOR_RGBA2BGR);
        writer.write(bgr);
      }
#endif
      if (soakFrames != 0 && (f + 1 == warmUpFrame || (f + 1) % 1000 == 0 || f + 1 == n)) {
        const core::ProcessMemory m = core::processMemory();
        if (f + 1 == warmUpFrame) atWarmUp = m;
        atLastFrame = m;
        std::printf("memory frame %u: VmRSS %ld kB VmHWM %ld kB heap %ld kB\n", f + 1, m.rssKb,
                    m.peakRssKb, m.heapKb);
        std::fflush(stdout);
      }
      if (strip && stripCount > 1) {
        // Evenly spaced, the last frame included.
        for (uint32_t k = 0; k < stripCount; ++k) {
          if (f == static_cast<uint64_t>(n - 1) * k / (stripCount - 1)) strip->add(rgba, w, k);
        }
      }
    }
    if (hashes) {
      hashes.close();
      if (!hashes) throw std::runtime_error(hashesPath + ": write failed");
      if (!hashesTemp.empty()) std::filesystem::rename(hashesTemp, hashesPath);
    }
    stats.finish();
    const std::vector<int64_t>& latency = stats.liveLatencyNs();
    if (strip) strip->write(stripPath);

    const int64_t span = lastEnd - firstStart;
    std::vector<uint32_t> sorted = passes;
    std::sort(sorted.begin(), sorted.end());
    std::printf("session %s: %u frames, %.2f s on the virtual clock\n",
                session.file.filename().c_str(), n, ms(span) * 1e-3);
    std::printf("fps %.2f (simulated board)\n",
                span > 0 ? static_cast<double>(n) * 1e9 / static_cast<double>(span) : 0.0);
    std::printf("passes median %u min %u max %u\n", sorted[sorted.size() / 2], sorted.front(),
                sorted.back());
    std::printf(
        "latency camera->screen median %.2f ms p99 %.2f ms (%zu frames with a live camera "
        "frame)\n",
        ms(percentile(latency, 50)), ms(percentile(latency, 99)), latency.size());
    std::printf(
        "camera outages %u, total %.2f s, longest %.2f s (frozen or lost picture; not "
        "in the latency)\n",
        stats.outages(), ms(stats.outageTotalNs()) * 1e-3, ms(stats.longestOutageNs()) * 1e-3);
    std::printf("led degraded %u frames, stale camera %u frames, attract %u frames\n", degraded,
                stale, attract);
    const bool replaySoak = drift.recorded() > warmUpFrame;
    if (soakFrames != 0) {
      const core::ProcessMemory& end = atLastFrame;
      std::printf(
          "soak memory: VmRSS %ld kB at frame %u, %ld kB at frame %u (growth %ld kB); "
          "heap in use %ld kB, %ld kB (growth %ld kB)\n",
          atWarmUp.rssKb, warmUpFrame, end.rssKb, n, end.rssKb - atWarmUp.rssKb, atWarmUp.heapKb,
          end.heapKb, end.heapKb - atWarmUp.heapKb);
      std::printf("soak log: %zu lines kept, %llu dropped\n", run.log().size(),
                  static_cast<unsigned long long>(run.log().dropped()));
      if (replaySoak) {
        std::fflush(stdout);
        const firmware_sim::FrameTimeDrift::Result d =
            drift.replay(session, options, warmUpFrame + 1);
        std::printf(
            "soak drift: frames %u-%u replayed after frame %u: identical pictures; board "
            "ms/frame median %.3f then, %.3f now, per-frame ratio median %.3f\n",
            d.firstFrame, d.lastFrame, n, d.firstMedianMs, d.replayMedianMs, d.ratio);
      }
    }
    if (bench) {
      std::printf("wall ms/frame on this machine: median %.2f p99 %.2f (%d threads, %s)\n",
                  ms(percentile(wallNs, 50)), ms(percentile(wallNs, 99)), flags.threads,
                  flags.isa.c_str());
      // The board's frame by stage (issue 13): the stages' means add up to the mean board
      // frame; the simulator's camera rendering is listed apart, as are the simulator's
      // own bookkeeping and hot-swaps (the difference to the wall time above).
      std::printf("board frame by stage, wall ms on this machine, %u frames:\n%s", n,
                  stageSamples.table().c_str());
      std::printf("peak RSS %.1f MB (VmHWM: the whole simulator, camera footage%s included)\n",
                  double(core::processMemory().peakRssKb) / 1024.0,
                  replaySoak ? " and the soak's replay" : "");
      if (!benchCsvPath.empty()) core::writeFileReplacing(benchCsvPath, stageSamples.csv());
    }
    return 0;
  });
}
