// penumbra-gl-replay: replays a frame trace through OpenGL ES 3.2 on Mesa (llvmpipe) as a
// second implementation of docs/pipeline-spec.md (gl_trace_replay.h), times it, and
// optionally compares bytes and speed with penumbra's own Renderer.
//
// Fairness: llvmpipe is told to use as many raster threads as the Renderer
// (LP_NUM_THREADS, set before the context is created; default 2 for a 2-core machine).
// GL times include the CPU set-up of the frame's triangles (clip, snap, planes), their
// upload with the background, glFinish() and the glReadPixels() read-back; Renderer times
// include its whole render().

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef PENUMBRA_GL_REPLAY_PNG
#include <png.h>
#endif

#include "bench/gl_replay/gl_context.h"
#include "bench/gl_replay/gl_trace_replay.h"
#include "bench/gl_replay/image_compare.h"
#include "core/cli.h"
#include "raster/frame_trace.h"
#include "raster/renderer.h"
#include "simd/targets.h"

namespace {

using Clock = std::chrono::steady_clock;
using penumbra::raster::FrameTrace;

struct Timing {
  double median = 0, min = 0;
};

Timing summarise(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  const size_t n = ms.size();
  Timing t;
  t.min = ms.front();
  t.median = n % 2 == 1 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
  return t;
}

template <typename F>
Timing timeFrames(int frames, F&& renderOnce) {
  std::vector<double> ms;
  ms.reserve(static_cast<size_t>(frames));
  for (int i = 0; i < frames; ++i) {
    const auto start = Clock::now();
    renderOnce();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  return summarise(std::move(ms));
}

void writeImage(const std::filesystem::path& path, const std::vector<uint8_t>& rgba, uint32_t width,
                uint32_t height) {
#ifdef PENUMBRA_GL_REPLAY_PNG
  if (path.extension() == ".png") {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = width;
    image.height = height;
    image.format = PNG_FORMAT_RGBA;
    if (png_image_write_to_file(&image, path.c_str(), 0, rgba.data(),
                                static_cast<png_int_32>(width * 4), nullptr) == 0) {
      throw std::runtime_error("cannot write " + path.string() + ": " + image.message);
    }
    return;
  }
#endif
  // Raw RGBA8, row 0 at the top, width*height*4 bytes.
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(rgba.data()), static_cast<std::streamsize>(rgba.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Replays a Penumbra frame trace through OpenGL ES 3.2 on Mesa (llvmpipe), following\n"
      "docs/pipeline-spec.md, and times it. Times per frame include the CPU set-up and upload\n"
      "of the frame content, glFinish() and the RGBA8\n"
      "read-back. --compare also renders with Penumbra's Renderer and prints one JSON\n"
      "object with the byte agreement and both speeds."};
  std::filesystem::path tracePath, outPath;
  int frames = 20;
  int threads = 2;
  bool compare = false;
  app.add_option("TRACE", tracePath, "frame trace (.json with its .bin sidecar)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--out", outPath,
                 "write the GL frame: PNG if the name ends in .png (and libpng was found), "
                 "else raw RGBA8 (row 0 at the top)");
  app.add_option("--frames", frames, "frames to time (each renders the whole trace)")
      ->check(penumbra::cli::NumberRange(1, 100000));
  app.add_option("--threads", threads, "Renderer threads and llvmpipe threads (LP_NUM_THREADS)")
      ->check(penumbra::cli::NumberRange(1, 256));
  app.add_flag("--compare", compare,
               "also render with Penumbra's Renderer (best ISA) and print a JSON comparison");
  return penumbra::cli::run("penumbra-gl-replay", app, argc, argv, [&] {
    // Must happen before Mesa creates its screen: llvmpipe reads it once.
    setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);

    const FrameTrace trace = penumbra::raster::loadTrace(tracePath);
    if (trace.frame.accumulation != penumbra::raster::Accumulation::kU8) {
      // GL blending rounds every pass to 8 bits (docs/pipeline-spec.md §8).
      throw std::runtime_error(tracePath.string() +
                               ": accumulation: gl_replay replays \"u8\" traces only");
    }
    const uint32_t width = trace.view.width, height = trace.view.height;
    std::vector<uint8_t> glImage(static_cast<size_t>(width) * height * 4);

    penumbra::gl::GlContext context;
    penumbra::gl::GlTraceReplay replay(trace.view);
    replay.render(trace.frame, glImage);  // warm-up: shader compilation, allocations
    const Timing glTime = timeFrames(frames, [&] { replay.render(trace.frame, glImage); });
    if (!outPath.empty()) writeImage(outPath, glImage, width, height);

    std::ostream& text = compare ? std::cerr : std::cout;
    text << "GL: " << context.renderer() << ", " << context.version() << " ("
         << context.displayKind() << "), LP_NUM_THREADS=" << threads << "\n";
    text << "GL replay " << width << "x" << height << ", " << frames << " frames: median "
         << glTime.median << " ms/frame, min " << glTime.min
         << " ms/frame (set-up + upload + draw + glFinish + read-back)\n";
    if (!compare) return 0;

    penumbra::raster::RenderOptions options;
    options.isa = penumbra::simd::bestIsa();
    options.threads = threads;
    penumbra::raster::Renderer renderer(trace.view, options);
    std::vector<uint8_t> ours(glImage.size());
    renderer.render(trace.frame, ours);  // warm-up
    const Timing ourTime = timeFrames(frames, [&] { renderer.render(trace.frame, ours); });
    const penumbra::gl::ImageDiff diff = penumbra::gl::compareImages(glImage, ours, width, height);
    text << "Penumbra " << penumbra::simd::isaName(options.isa) << ", " << threads
         << " threads: median " << ourTime.median << " ms/frame, min " << ourTime.min
         << " ms/frame\n";

    nlohmann::json j;
    j["trace"] = tracePath.string();
    j["width"] = width;
    j["height"] = height;
    j["frames"] = frames;
    j["identical_byte_share"] = diff.identicalByteShare;
    j["max_abs_diff"] = diff.maxAbsDiff;
    j["max_abs_diff_shift_tolerant"] = diff.maxAbsDiffShiftTolerant;
    j["mean_abs_diff"] = diff.meanAbsDiff;
    j["differing_pixels"] = diff.differingPixels;
    j["penumbra_ms_median"] = ourTime.median;
    j["penumbra_ms_min"] = ourTime.min;
    j["gl_ms_median"] = glTime.median;
    j["gl_ms_min"] = glTime.min;
    j["speed_ratio"] = ourTime.median > 0 ? glTime.median / ourTime.median : 0.0;
    j["threads"] = threads;
    j["mesa_threads"] = threads;
    j["isa"] = penumbra::simd::isaName(options.isa);
    j["gl_renderer"] = context.renderer();
    std::cout << j.dump(2) << "\n";
    return 0;
  });
}
