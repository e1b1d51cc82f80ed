#include "apps/compare_command.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#ifdef PENUMBRA_HAVE_METRICS
#include <nlohmann/json.hpp>

#include "core/cli.h"
#include "core/image.h"
#include "reference/image_metrics.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_METRICS
namespace {

struct CompareCommand {
  std::string a, b, mask, json, heatmap;
  double ppd = reference::FlipOptions{}.pixelsPerDegree;

  int run() const {
    // Everything is read and computed before any file is written, so bad input leaves no
    // partial output behind.
    const core::Image8 ref = reference::loadRgb8(a);
    const core::Image8 test = reference::loadRgb8(b);
    std::optional<core::Image8> m;
    if (!mask.empty()) m = reference::loadMask(mask);
    reference::CompareOptions options;
    options.flip.pixelsPerDegree = ppd;
    const reference::ImageComparison c =
        reference::compareImages(ref, test, m ? &*m : nullptr, options);
    nlohmann::json j = reference::toJson(c);
    j["reference"] = a;
    j["test"] = b;
    if (m) j["mask_file"] = mask;
    const std::string text = j.dump(2) + "\n";
    if (!heatmap.empty()) reference::writeHeatmapPng(heatmap, c.flipMap, c.width, c.height);
    if (json.empty()) {
      std::cout << text;
    } else {
      std::ofstream out(json);
      out << text;
      if (!out) throw std::runtime_error(json + ": cannot write JSON");
      const reference::RegionErrors& r = c.masked ? *c.masked : c.frame;
      std::printf(
          "%s: mean_abs %.4f p99_abs %u max_abs %u psnr %s ssim %.5f flip_mean %.5f -> %s\n",
          c.masked ? "mask" : "frame", r.meanAbs, r.p99Abs, r.maxAbs,
          std::isinf(r.psnr) ? "inf" : std::to_string(r.psnr).c_str(), c.ssim, r.flipMean,
          json.c_str());
    }
    return 0;
  }
};

}  // namespace
#endif

std::vector<Command> addCompareCommands([[maybe_unused]] CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_METRICS
  auto cmd = std::make_shared<CompareCommand>();
  CLI::App* c = app.add_subcommand(
      "compare", "Image metrics of B against reference A: abs error, PSNR, SSIM, FLIP");
  c->add_option("A", cmd->a, "reference image (PNG)")->required();
  c->add_option("B", cmd->b, "test image (PNG, same size)")->required();
  c->add_option("--mask", cmd->mask, "8-bit mask PNG, nonzero = inside (e.g. the shadow region)");
  c->add_option("--json", cmd->json, "write the JSON here instead of stdout");
  c->add_option("--heatmap", cmd->heatmap, "write the FLIP error map as a colour PNG");
  c->add_option("--ppd", cmd->ppd, "FLIP viewing condition: pixels per degree")
      ->check(cli::NumberRange(1.0, 1000.0))
      ->capture_default_str();
  commands.push_back({c, [cmd] { return cmd->run(); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
