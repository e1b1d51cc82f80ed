// Charts (a) and (b) data: ms/frame and error against the reference over blending passes ×
// shadow-map size × source-set share (Gibson 2003 §4 source share, §7.2 map size, §8–9
// passes; design §4), on the showroom, through the real per-frame pipeline
// (shadow::FrameLoop, as `penumbra render` / `profile` and the kiosk).
//
// The reference is pluggable: --reference REF.png (e.g. the ray-traced ground truth, once it
// lands); without it, a high-quality Penumbra render (the largest share in --shares, the most
// passes, a 2048² shadow map) stands in — the chart titles say which. The error region is
// --mask, or the reference's shadow region (reference/shadow_region.h: the pixels outside
// the product where the reference differs from the zero-pass frame by a level or more).
//
//   penumbra-accuracy-sweep data/showroom/showroom.json --csv sweep.csv
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>

#include "core/cli.h"
#include "core/image.h"
#include "lighting/precompute.h"
#include "raster/renderer.h"
#include "reference/image_metrics.h"
#include "reference/shadow_region.h"
#include "scene/image_io.h"
#include "scene/scene_file.h"
#include "shadow/frame_compositor.h"
#include "shadow/frame_loop.h"

namespace {

using namespace penumbra;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ms/frame and error over passes x shadow-map size x source share (charts a, b)"};
  std::string scenePath, csvPath, referencePath, maskPath, referenceOut;
  std::vector<double> shares{0.5, 0.7, 0.9};
  std::vector<int> maps{64, 128, 256, 512};
  std::vector<int> passes{1, 2, 5, 10, 20, 50, 100, 200};
  std::vector<int> curvePasses{1,  2,  3,  4,  5,  6,  8,   10,  12,  15, 20,
                               25, 30, 40, 50, 60, 80, 100, 120, 150, 200};
  double curveShare = 0.7;
  int curveMap = 256, frames = 5, threads = 2, refMap = 2048;
  app.add_option("SCENE", scenePath, "scene file (data/showroom/showroom.json)")->required();
  app.add_option("--csv", csvPath, "CSV output")->required();
  app.add_option("--reference", referencePath, "reference PNG (default: a Penumbra render)");
  app.add_option("--mask", maskPath, "error region PNG (default: the reference's shadow)");
  app.add_option("--reference-out", referenceOut, "write the reference used as PNG");
  app.add_option("--shares", shares, "source-set power shares")->delimiter(',');
  app.add_option("--maps", maps, "shadow-map sizes")->delimiter(',');
  app.add_option("--passes", passes, "pass counts of the grid")->delimiter(',');
  app.add_option("--curve-passes", curvePasses, "pass counts at the curve's share and map")
      ->delimiter(',');
  app.add_option("--curve-share", curveShare, "share of the ms/frame-against-passes curve")
      ->capture_default_str();
  app.add_option("--curve-map", curveMap, "map size of that curve")->capture_default_str();
  app.add_option("--reference-map", refMap, "map size of the Penumbra reference")
      ->capture_default_str();
  app.add_option("--frames", frames, "timed frames per configuration (median)")
      ->check(cli::NumberRange(1, 1000))
      ->capture_default_str();
  app.add_option("--threads", threads, "render threads")
      ->check(cli::NumberRange(1, 256))
      ->capture_default_str();
  return penumbra::cli::run("penumbra-accuracy-sweep", app, argc, argv, [&] {
    raster::RenderOptions ro;
    ro.isa = simd::bestIsa();
    ro.threads = threads;
    const scene::SceneDescription scene = scene::loadSceneFile(scenePath);
    std::vector<lighting::StageTiming> timings;
    auto precompute = [&](double share) {
      lighting::PrecomputeOptions o;
      o.powerShare = share;
      return lighting::precomputeBundle(scene, o, timings);
    };
    std::sort(shares.begin(), shares.end());
    const double refShare = shares.back();
    const shadow::SceneBundle refBundle = precompute(refShare);
    const shadow::ProductPose pose = refBundle.startPose;
    const uint32_t w = refBundle.view.width, h = refBundle.view.height;

    // The zero-pass frame: background + product, no shadow.
    shadow::FrameLoop zero(refBundle, 256, ro);
    zero.still(pose, 0);

    core::Image8 ref;
    std::string refLabel;
    if (!referencePath.empty()) {
      ref = reference::loadRgb8(referencePath);
      refLabel = "reference " + std::filesystem::path(referencePath).filename().string();
    } else {
      shadow::FrameLoop r(refBundle, uint32_t(refMap), ro);
      const int most = *std::max_element(curvePasses.begin(), curvePasses.end());
      r.still(pose, size_t(std::max(most, *std::max_element(passes.begin(), passes.end()))));
      ref = reference::fromRgba8(r.rgba, w, h, "penumbra-reference");
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "reference = Penumbra %u passes, share %.2f, %d map (ray-traced one pending)",
                    r.stats.passes, refShare, refMap);
      refLabel = buf;
    }
    if (!referenceOut.empty()) {
      std::vector<uint8_t> rgba(size_t(w) * h * 4, 255);
      for (size_t i = 0; i < size_t(w) * h; ++i) {
        for (size_t k = 0; k < 3; ++k) rgba[4 * i + k] = ref.pixels[3 * i + k];
      }
      scene::writePng(referenceOut, w, h, rgba);
    }
    core::Image8 mask;
    if (!maskPath.empty()) {
      mask = reference::loadMask(maskPath);
    } else {
      if (ref.width != w || ref.height != h) {
        throw reference::MetricsError(ref.name + ": size differs from the showroom's frame");
      }
      mask = reference::shadowRegion(ref, zero.rgba, refBundle.background, "shadow region");
    }

    std::ofstream out(csvPath);
    if (!out) throw std::runtime_error(csvPath + ": cannot write");
    out << "share,map,passes_asked,passes,sources,ms_frame,mean_abs_shadow,p99_abs_shadow,"
           "max_abs_shadow,mean_abs_frame,psnr,ssim,shadow_pixels,curve,reference\n";
    reference::CompareOptions co;
    co.computeFlip = false;  // FLIP per configuration would dominate the sweep
    for (double share : shares) {
      const shadow::SceneBundle bundle = share == refShare ? refBundle : precompute(share);
      for (int map : maps) {
        const bool curve = share == curveShare && map == curveMap;
        std::set<int> list(passes.begin(), passes.end());
        if (curve) list.insert(curvePasses.begin(), curvePasses.end());
        shadow::FrameLoop r(bundle, uint32_t(map), ro);
        for (int n : list) {
          std::vector<double> ms;
          for (int f = 0; f <= frames; ++f) {
            // The product slides a little every frame, as on the kiosk (and in `profile`).
            shadow::ProductPose p = pose;
            p.x += 0.01f * float(f % 7);
            r.step(p, size_t(n));
            if (f > 0) ms.push_back(double(r.frameNs) * 1e-6);
          }
          r.still(pose, size_t(n));
          const reference::ImageComparison c = reference::compareImages(
              ref, reference::fromRgba8(r.rgba, w, h, "render"), &mask, co);
          const reference::RegionErrors& s = *c.masked;
          out << share << ',' << map << ',' << n << ',' << r.stats.passes << ','
              << bundle.sets.sources.size() << ',' << median(ms) << ',' << s.meanAbs << ','
              << s.p99Abs << ',' << s.maxAbs << ',' << c.frame.meanAbs << ','
              << (std::isinf(c.frame.psnr) ? 999.0 : c.frame.psnr) << ',' << c.ssim << ','
              << s.pixels << ',' << (curve ? 1 : 0) << ",\"" << refLabel << "\"\n";
          std::printf(
              "share %.2f map %4d passes %3d (%3u) ms %7.3f mean_abs %.3f p99 %u ssim %.5f\n",
              share, map, n, r.stats.passes, median(ms), s.meanAbs, s.p99Abs, c.ssim);
          std::fflush(stdout);
        }
      }
    }
    if (!out) throw std::runtime_error(csvPath + ": write failed");
    return 0;
  });
}
