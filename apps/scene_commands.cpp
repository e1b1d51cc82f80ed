#include "apps/scene_commands.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/render_flags.h"
#include "core/cli.h"
#include "core/clock.h"
#include "core/json_reader.h"
#include "core/process_memory.h"
#include "raster/renderer.h"
#include "scene/image_io.h"
#include "scene/sha256.h"
#include "shadow/frame_loop.h"
#include "shadow/frame_runs.h"
#include "shadow/render_settings.h"
#include "shadow/scene_bundle.h"
#ifdef PENUMBRA_HAVE_LIGHTING
#include "lighting/precompute.h"
#include "scene/scene_file.h"
#endif

namespace penumbra::apps {

shadow::ProductPose parsePose(const std::string& text, uint32_t product) {
  std::vector<float> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw cli::UsageError("--pose: '" + item + "' is not a number");
    }
  }
  if (values.size() < 3 || values.size() > 4) {
    throw cli::UsageError("--pose needs X,Y,Z or X,Y,Z,YAW (got '" + text + "')");
  }
  return {product, values[0], values[2], values.size() == 4 ? values[3] : 0.0f, values[1]};
}

shadow::ProductPose requestedPose(const shadow::SceneBundle& b, const std::string& pose,
                                  int product) {
  shadow::ProductPose p = b.startPose;
  if (!pose.empty()) p = parsePose(pose, p.product);
  if (product >= 0) p.product = static_cast<uint32_t>(product);
  if (p.product >= b.products.size()) {
    throw cli::UsageError("--product " + std::to_string(p.product) + ": the bundle has " +
                          std::to_string(b.products.size()) + " products");
  }
  return p;
}

namespace {

// bench/plot_profile.py: installed at bin/../share/penumbra/scripts (packaging/CMakeLists.txt),
// found from this program's own path; in a build tree, in the sources.
std::filesystem::path plotScript() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    auto installed =
        self.parent_path().parent_path() / "share" / "penumbra" / "scripts" / "plot_profile.py";
    if (std::filesystem::is_regular_file(installed)) return installed;
  }
  return std::filesystem::path(PENUMBRA_SOURCE_DIR) / "bench" / "plot_profile.py";
}

struct SceneFlags {
  std::string bundle;
  std::string pose;  // empty: the bundle's start pose
  int product = -1;  // -1: the pose's product
  RenderFlags render;
};

void addSceneFlags(CLI::App* cmd, SceneFlags& f) {
  cmd->add_option("BUNDLE", f.bundle, "scene bundle (penumbra precompute)")->required();
  cmd->add_option("--pose", f.pose,
                  "product position: X,Y,Z[,YAW_DEGREES] (Y: lift above the floor, metres)");
  cmd->add_option("--product", f.product, "product index (default: the start pose's)");
  addRenderFlags(cmd, f.render);
}

shadow::ProductPose poseOf(const SceneFlags& f, const shadow::SceneBundle& b) {
  return requestedPose(b, f.pose, f.product);
}

// One product in the showroom, frame after frame (design §1, per frame): the bundle, the
// pose the flags ask for, and the per-frame loop (shadow/frame_loop.h).
struct Session {
  // `fineProxyPasses` >= 0 draws every product's fine proxy in that many of 50 passes instead
  // of the bundle's counts (profile's --fine-proxy-passes).
  explicit Session(const SceneFlags& flags, int fineProxyPasses = -1)
      : bundle(shadow::loadBundle(flags.bundle)),
        pose(poseOf(flags, bundle)),
        loop(bundle, shadow::compositorOptions(settingsOf(bundle, fineProxyPasses)),
             toOptions(flags.render)) {}
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const shadow::SceneBundle bundle;
  const shadow::ProductPose pose;
  shadow::FrameLoop loop;

 private:
  static shadow::RenderSettings settingsOf(const shadow::SceneBundle& b, int fineProxyPasses) {
    shadow::RenderSettings s = b.settings;
    if (fineProxyPasses >= 0) {
      s.fineProxyPasses = static_cast<uint32_t>(fineProxyPasses);
      s.productFineProxyPasses.clear();
    }
    return s;
  }
};

// --- render ------------------------------------------------------------------------------

struct RenderCommand {
  SceneFlags scene;
  int passes = 0;
  double fps = 0;
  std::string out, trace;
  bool hash = false;

  int run() const {
    Session session(scene);
    const shadow::SceneBundle& bundle = session.bundle;
    const shadow::ProductPose& pose = session.pose;
    shadow::FrameLoop& loop = session.loop;
    const shadow::CompositeStats& stats = loop.stats;
    uint32_t n = static_cast<uint32_t>(passes);
    if (fps > 0) {
      // Frame-rate control (Gibson 2003 §8): let the controller settle on this machine,
      // then keep its last frame.
      n = shadow::settleFrameRate(loop, pose, shadow::renderControllerOptions(fps, bundle.settings))
              .passes;
    } else {
      // The first frame measures where the product blocks the light, the second takes its
      // intensity transfers at those occluded shares (docs/fig3.md).
      loop.still(pose, n);
    }
    const double msFrame = double(loop.frameNs) * 1e-6;
    std::printf("product %s at (%.3f, %.3f, %.3f) yaw %.1f\n",
                bundle.products[pose.product].name.c_str(), double(pose.x), double(pose.lift),
                double(pose.z), double(pose.yawDegrees));
    const shadow::ShaftHierarchy& h = loop.compositor.hierarchy();
    std::printf("shaft_hierarchy shafts %zu leaf_shafts %zu memory_kb %.1f\n", h.shaftCount(),
                h.leafShaftCount(), double(h.memoryBytes()) / 1024.0);
    std::printf(
        "passes %u (asked %u) occluded_sources %u receivers %u shafts_visited %u graded_vertices "
        "%u "
        "receiver_vertices %u\n",
        stats.passes, n, stats.occludedSources, stats.receiverPatches, stats.shaftsVisited,
        stats.gradedVertices, stats.receiverVertices);
    if (stats.skippedClusters > 0) {
      std::fprintf(stderr,
                   "penumbra: warning: %u of %u source clusters lie inside the product's "
                   "bounding sphere (is it larger than the room?): they cast no shadow\n",
                   stats.skippedClusters, stats.clusters);
    }
    std::printf("ms_frame %.3f\n", msFrame);
    shadow::FrameStageSamples stages;
    stages.add(loop.stages);
    std::fputs(stages.table().c_str(), stdout);
    if (!trace.empty()) raster::saveTrace({bundle.view, loop.frame}, trace);
    if (!out.empty()) scene::writePng(out, bundle.view.width, bundle.view.height, loop.rgba);
    if (hash) std::printf("sha256 %s\n", scene::sha256Hex(loop.rgba).c_str());
    return 0;
  }
};

// --- profile -----------------------------------------------------------------------------

struct ProfileCommand {
  SceneFlags scene;
  std::vector<int> passes{1, 5, 10, 20, 50, 100, 200};
  int frames = 20;
  int shadowMapSize = 0;     // 0: the bundle's (its settings)
  int fineProxyPasses = -1;  // -1: the bundle's (its settings)
  std::string csv, plot;

  int run() const {
    Session session(scene, fineProxyPasses);
    shadow::FrameLoop& loop = session.loop;
    if (shadowMapSize != 0) loop.compositor.setShadowMapSize(static_cast<uint32_t>(shadowMapSize));
    // The size the passes draw: the flag's, or the bundle's settings (bench/board_cost_model.py
    // prices passes x size^2 from this column).
    const uint32_t mapSize = shadowMapSize != 0 ? static_cast<uint32_t>(shadowMapSize)
                                                : session.bundle.settings.shadowMapSize;
    std::ofstream out(csv);
    if (!out) throw std::runtime_error(csv + ": cannot write");
    // ms_total: the median frame; ms_mean: the mean frame, which the stages' means (the
    // stage_* columns, shadow/frame_stages.h) add up to.
    using shadow::FrameStage;
    out << "passes_asked,passes,occluded_sources,receivers,shafts_visited,shadowed_pixels,"
           "ms_total,ms_mean";
    for (size_t i = 0; i < shadow::kFrameStageCount; ++i) {
      if (!shadow::onBoard(static_cast<FrameStage>(i))) continue;
      std::string name = shadow::frameStageName(static_cast<FrameStage>(i));
      std::replace(name.begin(), name.end(), ' ', '_');
      out << ",stage_" << name;
    }
    // The product's vertices: with the passes and pixels, what the board's cost model charges
    // (shadow/frame_cost_model.h); the product slides, so it is shaded in every frame. The
    // occluder triangles the passes drew: what a pass drawing the fine proxy costs more.
    out << ",product_vertices,shadow_map_size,shadow_map_triangles\n";
    // The console: the median frame, then the stages' means grouped (traversal with clusters;
    // room and product transfers; raster: objects, passes, finish; rest: every other stage).
    std::printf("%6s %6s %9s %9s %9s %9s %9s %9s %9s\n", "asked", "passes", "pixels", "median",
                "mean", "travers", "transfer", "rest", "raster");
    for (int asked : passes) {
      const shadow::PassProfile r =
          shadow::profilePasses(loop, session.pose, size_t(asked), frames);
      const shadow::FrameStageSamples& s = r.stages;
      out << asked << ',' << r.passes << ',' << r.occludedSources << ',' << r.receivers << ','
          << r.shaftsVisited << ',' << r.shadowedPixels << ',' << r.total << ',' << s.meanBoardMs();
      for (size_t i = 0; i < shadow::kFrameStageCount; ++i) {
        if (!shadow::onBoard(static_cast<FrameStage>(i))) continue;
        out << ',' << s.meanMs(static_cast<FrameStage>(i));
      }
      out << ',' << loop.stats.productVertices << ',' << mapSize << ',' << r.shadowMapTriangles
          << '\n';
      const auto sum = [&](std::initializer_list<FrameStage> stages) {
        double ms = 0;
        for (FrameStage stage : stages) ms += s.meanMs(stage);
        return ms;
      };
      const double transfers = sum({FrameStage::kRoomTransfers, FrameStage::kProductTransfers});
      const double raster =
          sum({FrameStage::kRasterObjects, FrameStage::kRasterPasses, FrameStage::kRasterFinish});
      const double traversal = sum({FrameStage::kTraversal, FrameStage::kClusters});
      std::printf("%6d %6u %9llu %9.3f %9.3f %9.4f %9.3f %9.3f %9.3f\n", asked, r.passes,
                  static_cast<unsigned long long>(r.shadowedPixels), r.total, s.meanBoardMs(),
                  traversal, transfers, s.meanBoardMs() - transfers - raster - traversal, raster);
    }
    out.close();
    if (!plot.empty()) {
      // A chart people already know how to read, drawn by matplotlib (design §4).
      const std::string command =
          "/usr/bin/python3 '" + plotScript().string() + "' '" + csv + "' '" + plot + "'";
      if (std::system(command.c_str()) != 0) {
        throw std::runtime_error("plotting failed (python3 with matplotlib is needed): " + command);
      }
    }
    return 0;
  }
};

// --- info --------------------------------------------------------------------------------

// What a bundle holds and the settings its frames are drawn with (issue 17: `penumbra info`).
nlohmann::json bundleInfo(const std::string& path, const shadow::SceneBundle& b) {
  nlohmann::json products = nlohmann::json::array();
  for (size_t i = 0; i < b.products.size(); ++i) {
    const shadow::ProductModel& p = b.products[i];
    products.push_back({{"index", i},
                        {"name", p.name},
                        {"triangles", p.mesh.triangleCount()},
                        {"proxy_triangles", p.proxy.triangleCount()},
                        {"fine_proxy_triangles", p.fineProxy.triangleCount()},
                        // Of kFineProxyReferencePasses (50) passes; 0 without a fine proxy.
                        {"fine_proxy_passes",
                         p.fineProxy.indices.empty()
                             ? 0u
                             : shadow::fineProxyPassesOf(b.settings, static_cast<uint32_t>(i))},
                        {"vertex_normals", !p.normals.empty()},
                        {"vertex_colours", !p.reflectances.empty()}});
  }
  const shadow::RenderSettings& s = b.settings;
  const shadow::IrradianceVolume& v = b.irradiance;
  return {{"bundle", path},
          {"view", {{"width", b.view.width}, {"height", b.view.height}}},
          {"room_triangles", b.view.staticMesh.triangleCount()},
          {"patches", b.patches.size()},
          {"sources", b.sets.sources.size()},
          {"power_share", b.sets.powerShare},
          {"receivers", b.sets.receivers.size()},
          {"receiver_vertices", b.transfers.receiverVertices.size()},
          {"transfer_entries", b.transfers.entryVertex.size()},
          {"irradiance_volume",
           v.empty() ? nlohmann::json(nullptr) : nlohmann::json{v.dims.x, v.dims.y, v.dims.z}},
          {"products", products},
          {"start_pose",
           {{"product", b.startPose.product},
            {"x", b.startPose.x},
            {"lift", b.startPose.lift},
            {"z", b.startPose.z},
            {"yaw_deg", b.startPose.yawDegrees}}},
          {"settings",
           {{"tuned", s.tuned},
            {"max_passes", s.maxPasses},
            {"shadow_map_sizes", shadow::shadowMapLadder(s)},
            {"fine_proxy_passes", s.fineProxyPasses},
            {"product_fine_proxy_passes", s.productFineProxyPasses},
            {"area_penumbrae", s.areaPenumbrae},
            {"prune_fraction", s.pruneFraction},
            {"receivers_per_leaf", s.receiversPerLeaf},
            {"texels_per_shadow_pixel", s.texelsPerShadowPixel}}}};
}

struct InfoCommand {
  std::string bundle;
  bool json = false;

  int run() const {
    const nlohmann::json j = bundleInfo(bundle, shadow::loadBundle(bundle));
    if (json) {
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    const auto str = [](const nlohmann::json& v) { return v.dump(); };
    std::cout << "bundle " << bundle << "\n"
              << "view " << str(j["view"]["width"]) << "x" << str(j["view"]["height"]) << ", "
              << str(j["room_triangles"]) << " room triangles, " << str(j["patches"])
              << " patches\n"
              << "light " << str(j["sources"]) << " sources (power share " << str(j["power_share"])
              << "), " << str(j["receivers"]) << " receivers, " << str(j["receiver_vertices"])
              << " receiver vertices, " << str(j["transfer_entries"]) << " transfers\n"
              << "irradiance_volume " << str(j["irradiance_volume"]) << "\n";
    for (const nlohmann::json& p : j["products"]) {
      std::cout << "product " << str(p["index"]) << " " << p["name"].get<std::string>() << ": "
                << str(p["triangles"]) << " triangles, proxy " << str(p["proxy_triangles"])
                << ", fine proxy " << str(p["fine_proxy_triangles"]);
      if (p["fine_proxy_triangles"].get<size_t>() > 0) {
        std::cout << " in " << str(p["fine_proxy_passes"]) << " of 50 passes";
      }
      std::cout << "\n";
    }
    const nlohmann::json& s = j["settings"];
    std::cout << "settings " << (s["tuned"].get<bool>() ? "tuned" : "defaults") << ": max_passes "
              << str(s["max_passes"]) << ", shadow_map_sizes " << str(s["shadow_map_sizes"])
              << ", fine_proxy_passes " << str(s["fine_proxy_passes"]) << ", area_penumbrae "
              << (s["area_penumbrae"].get<bool>() ? "on" : "off") << ", prune_fraction "
              << str(s["prune_fraction"]) << ", receivers_per_leaf " << str(s["receivers_per_leaf"])
              << ", texels_per_shadow_pixel "
              << (s["texels_per_shadow_pixel"].get<double>() > 0
                      ? core::formatNumber(s["texels_per_shadow_pixel"].get<double>())
                      : std::string("off"))
              << "\n";
    return 0;
  }
};

}  // namespace

#ifdef PENUMBRA_HAVE_LIGHTING
shadow::SceneBundle precomputeScene(const std::string& scenePath,
                                    const lighting::PrecomputeOptions& options,
                                    std::vector<lighting::StageTiming>& timings,
                                    double proxyScale) {
  scene::SceneDescription scene = scene::loadSceneFile(scenePath);
  if (proxyScale > 0) scene::scaleShadowProxies(scene, proxyScale);
  // What the models' loaders could not honour and implausible sizes (a unit slip): not
  // errors, but a technician must see them.
  for (const scene::Product& p : scene.products) {
    for (const std::string& w : p.warnings) {
      std::fprintf(stderr, "penumbra: warning: product %s: %s\n", p.name.c_str(), w.c_str());
    }
  }
  return lighting::precomputeBundle(
      scene, options, timings, [](const std::string& stage, int index, int count) {
        std::fprintf(stderr, "[%d/%d] %s ...\n", index + 1, count, stage.c_str());
      });
}
#endif

std::vector<Command> addSceneCommands(CLI::App& app) {
  std::vector<Command> commands;

#ifdef PENUMBRA_HAVE_LIGHTING
  auto precompute = std::make_shared<std::pair<std::string, std::string>>();
  auto precomputeOptions = std::make_shared<lighting::PrecomputeOptions>();
  auto proxyScale = std::make_shared<double>(0.0);
  CLI::App* pre = app.add_subcommand("precompute", "Scene file -> scene bundle (Gibson 2003 §4-5)");
  pre->add_option("SCENE", precompute->first, "scene description (.json)")->required();
  pre->add_option("-o,--out", precompute->second, "bundle to write")->required();
  pre->add_option("--power-share", precomputeOptions->powerShare,
                  "share of emitted power in the source set (§4); default: the scene file's "
                  "power_share, else 0.7")
      ->check(cli::NumberRange(0.01, 1.0));
  pre->add_option("--samples", precomputeOptions->samplesPerSide,
                  "visibility samples per source patch side (§5)")
      ->check(cli::NumberRange(1, 16))
      ->capture_default_str();
  pre->add_option("--patch-size", precomputeOptions->patchSize,
                  "patch size in metres (default: the scene file's)")
      ->check(cli::NumberRange(0.02, 10.0));
  pre->add_option("--emitter-patch-size", precomputeOptions->emitterPatchSize,
                  "cut emitters into patches of at most this size in metres, each a source "
                  "(default: as the scene file cuts them)")
      ->check(cli::NumberRange(0.02, 10.0));
  pre->add_option("--proxy-scale", *proxyScale,
                  "every product's shadow proxies simplified to this share of the scene file's "
                  "proxy_triangles and fine_proxy_triangles (default: as the file says)")
      ->check(cli::NumberRange(0.01, 16.0));
  pre->add_option("--threads", precomputeOptions->threads, "threads")
      ->check(cli::NumberRange(1, 256))
      ->capture_default_str();
  commands.push_back(
      {pre, [precompute, precomputeOptions, proxyScale] {
         core::Stopwatch watch;
         std::vector<lighting::StageTiming> timings;
         const shadow::SceneBundle bundle =
             precomputeScene(precompute->first, *precomputeOptions, timings, *proxyScale);
         shadow::saveBundle(bundle, precompute->second);
         for (const auto& t : timings) {
           std::printf("stage %-22s %9.1f ms\n", t.stage.c_str(), t.ms);
         }
         std::printf("patches %zu sources %zu receivers %zu transfer_entries %zu\n",
                     bundle.patches.size(), bundle.sets.sources.size(),
                     bundle.sets.receivers.size(), bundle.transfers.entryVertex.size());
         std::printf("total %.1f ms -> %s\n", watch.lap(), precompute->second.c_str());
         std::printf("peak RSS %.1f MB\n", double(core::processMemory().peakRssKb) / 1024.0);
         return 0;
       }});
#endif

  auto info = std::make_shared<InfoCommand>();
  CLI::App* in = app.add_subcommand("info", "What a scene bundle holds and its render settings");
  in->add_option("BUNDLE", info->bundle, "scene bundle (penumbra precompute)")->required();
  in->add_flag("--json", info->json, "print it as JSON");
  commands.push_back({in, [info] { return info->run(); }});

  auto render = std::make_shared<RenderCommand>();
  CLI::App* r = app.add_subcommand("render", "One frame of a product in the showroom");
  addSceneFlags(r, render->scene);
  auto* passOpt = r->add_option("--passes", render->passes, "blending passes (source clusters)")
                      ->check(cli::NumberRange(1, 257));
  auto* fpsOpt = r->add_option("--fps", render->fps, "let the frame-rate controller pick passes")
                     ->check(cli::NumberRange(1.0, 1000.0));
  passOpt->excludes(fpsOpt);
  r->add_option("--out", render->out, "write the frame as PNG");
  r->add_option("--trace", render->trace, "write the frame trace (docs/trace-format.md)");
  r->add_flag("--hash", render->hash, "print `sha256 <hex>` of the RGBA8 frame");
  commands.push_back({r, [render, passOpt, fpsOpt] {
                        if (passOpt->count() == 0 && fpsOpt->count() == 0) {
                          throw cli::UsageError("render needs --passes N or --fps F");
                        }
                        return render->run();
                      }});

  auto profile = std::make_shared<ProfileCommand>();
  CLI::App* p = app.add_subcommand("profile", "Time per stage against the number of passes");
  addSceneFlags(p, profile->scene);
  cli::addNumberList(p, "--passes", profile->passes, "pass counts, comma-separated", 1, 257);
  p->add_option("--frames", profile->frames, "timed frames per pass count")
      ->check(cli::NumberRange(1, 10000))
      ->capture_default_str();
  p->add_option("--shadow-map-size", profile->shadowMapSize,
                "shadow-map side in texels, a multiple of 16 (default: the bundle's settings, "
                "`penumbra info`)")
      ->check(CLI::Range(16, 4096));  // and a multiple of 16: FrameCompositor::setShadowMapSize
  p->add_option("--fine-proxy-passes", profile->fineProxyPasses,
                "passes of 50 that draw every product's fine shadow proxy, the same share of "
                "more (default: the bundle's settings)")
      ->check(CLI::Range(0, 257));
  p->add_option("--csv", profile->csv, "CSV output")->required();
  p->add_option("--plot", profile->plot, "PNG chart (matplotlib)");
  commands.push_back({p, [profile] { return profile->run(); }});
  return commands;
}

}  // namespace penumbra::apps
