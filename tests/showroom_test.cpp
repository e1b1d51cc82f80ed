// The showroom pipeline end to end (Gibson 2003 §4–8): data/showroom/showroom.json through
// precompute, the frame compositor and the renderer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "lighting/precompute.h"
#include "raster/renderer.h"
#include "scene/scene_file.h"
#include "scene/sha256.h"
#include "shadow/frame_compositor.h"
#include "tests/scratch_dir.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

const shadow::SceneBundle& showroom() {
  static const shadow::SceneBundle bundle = [] {
    const scene::SceneDescription scene =
        scene::loadSceneFile(fs::path(PENUMBRA_DATA_DIR) / "showroom" / "showroom.json");
    std::vector<lighting::StageTiming> timings;
    return lighting::precomputeBundle(scene, {}, timings);
  }();
  return bundle;
}

std::vector<uint8_t> renderPose(const shadow::ProductPose& pose, size_t passes,
                                const raster::RenderOptions& options,
                                shadow::CompositeStats* statsOut = nullptr) {
  shadow::FrameCompositor compositor(showroom(), {});
  raster::FrameContent frame;
  shadow::CompositeStats stats;
  compositor.compose(pose, passes, 1, frame, stats);
  if (statsOut != nullptr) *statsOut = stats;
  raster::Renderer renderer(showroom().view, options);
  std::vector<uint8_t> rgba(showroom().background.size());
  renderer.render(frame, rgba);
  return rgba;
}

std::vector<uint8_t> fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Showroom, PrecomputeIsDeterministicAcrossThreadCounts) {
  const scene::SceneDescription scene =
      scene::loadSceneFile(fs::path(PENUMBRA_DATA_DIR) / "showroom" / "showroom.json");
  std::vector<lighting::StageTiming> timings;
  lighting::PrecomputeOptions one, two;
  one.threads = 1;
  two.threads = 3;
  const fs::path a = test::scratchPath("showroom-1.bundle");
  const fs::path b = test::scratchPath("showroom-3.bundle");
  shadow::saveBundle(lighting::precomputeBundle(scene, one, timings), a);
  shadow::saveBundle(lighting::precomputeBundle(scene, two, timings), b);
  EXPECT_EQ(fileBytes(a), fileBytes(b));
  const shadow::SceneBundle loaded = shadow::loadBundle(a);
  EXPECT_EQ(loaded.view, showroom().view);
  EXPECT_GE(loaded.patches.size(), 1000u);
  EXPECT_GT(loaded.sets.sources.size(), 10u);
  fs::remove(a);
  fs::remove(b);
}

TEST(Showroom, ProductFarFromEverythingLeavesTheBackground) {
  shadow::CompositeStats stats;
  const auto frame = renderPose({0, 100.0f, 100.0f, 0.0f}, 50, {simd::bestIsa(), 2, 32}, &stats);
  EXPECT_EQ(stats.occludedSources, 0u);
  EXPECT_EQ(stats.passes, 0u);
  EXPECT_EQ(frame, showroom().background);
}

// In view but outside every shaft (design §5): the teapot floating half a metre in front of
// the camera, where no source-receiver shaft passes (the lights shine on the room ahead of
// it). The traversal finds no source, so there is no pass and only the product is drawn.
TEST(Showroom, ProductInViewOutsideEveryShaftGetsNoPass) {
  const shadow::ProductPose pose{2, 0.75f, 0.75f, 0.0f, 1.2f};
  shadow::CompositeStats stats;
  const auto frame = renderPose(pose, 50, {simd::bestIsa(), 2, 32}, &stats);
  EXPECT_EQ(stats.occludedSources, 0u);
  EXPECT_EQ(stats.passes, 0u);
  size_t productBytes = 0;
  for (size_t i = 0; i < frame.size(); ++i) productBytes += frame[i] != showroom().background[i];
  EXPECT_GT(productBytes, 1000u) << "the product must be in view";
}

// A product larger than the room holds the lights inside its bounding sphere: no light
// frustum can enclose it, so those clusters get no pass and their shadow is missing. Not
// silent: the stats count them (`penumbra render` warns on stderr).
TEST(Showroom, ProductLargerThanTheRoomReportsItsMissingShadow) {
  shadow::SceneBundle huge = showroom();
  for (core::Mesh* m : {&huge.products[0].mesh, &huge.products[0].proxy}) {
    for (core::Vec3& p : m->positions) p = {p.x * 12.0f, p.y * 12.0f, p.z * 12.0f};
  }
  shadow::FrameCompositor compositor(huge, {});
  raster::FrameContent frame;
  shadow::CompositeStats stats;
  compositor.compose(huge.startPose, 50, 1, frame, stats);
  EXPECT_GT(stats.clusters, 0u);
  EXPECT_EQ(stats.skippedClusters, stats.clusters);
  EXPECT_EQ(stats.passes, 0u);
  shadow::FrameCompositor normal(showroom(), {});
  normal.compose(showroom().startPose, 50, 1, frame, stats);
  EXPECT_EQ(stats.skippedClusters, 0u);
  EXPECT_GT(stats.passes, 0u);
}

TEST(Showroom, TheChairDarkensItsSurroundings) {
  shadow::CompositeStats stats;
  const shadow::ProductPose pose = showroom().startPose;
  const auto frame = renderPose(pose, 50, {simd::bestIsa(), 2, 32}, &stats);
  EXPECT_GT(stats.passes, 10u);
  EXPECT_GT(stats.receiverPatches, 0u);
  // Outside the product, a shadow only removes light.
  const auto noProduct = renderPose({pose.product, 100.0f, 100.0f, 0.0f}, 50, {});
  size_t darker = 0;
  for (size_t i = 0; i < frame.size(); i += 4) {
    for (int c = 0; c < 3; ++c) darker += frame[i + size_t(c)] < noProduct[i + size_t(c)];
  }
  EXPECT_GT(darker, 5000u);
}

TEST(Showroom, FramesAreIdenticalOnEveryTargetAndThreadCount) {
  const shadow::ProductPose pose{1, 2.5f, 2.0f, 30.0f};  // the bunny, turned
  const std::string reference = scene::sha256Hex(renderPose(pose, 20, {simd::Isa::kScalar, 1, 32}));
  for (simd::Isa isa : simd::supportedIsas()) {
    for (int threads : {1, 2, 4}) {
      EXPECT_EQ(scene::sha256Hex(renderPose(pose, 20, {isa, threads, 16})), reference)
          << simd::isaName(isa) << " threads " << threads;
    }
  }
}

TEST(Showroom, EnoughPassesGiveOneClusterPerBlockedSource) {
  shadow::CompositeStats few, all;
  renderPose(showroom().startPose, 5, {}, &few);
  renderPose(showroom().startPose, 257, {}, &all);
  EXPECT_EQ(few.clusters, 5u);
  EXPECT_EQ(all.clusters, all.occludedSources);  // §8: n = all leaves is the per-patch case
  EXPECT_EQ(few.occludedSources, all.occludedSources);
}

TEST(Showroom, ComposingAgainGivesTheSameFrame) {
  shadow::FrameCompositor compositor(showroom(), {});
  raster::FrameContent a, b;
  shadow::CompositeStats stats;
  compositor.compose(showroom().startPose, 30, 1, a, stats);
  compositor.compose({0, 1.0f, 1.0f, 45.0f}, 30, 2, b, stats);  // elsewhere in between
  compositor.compose(showroom().startPose, 30, 3, b, stats);
  EXPECT_EQ(a, b);
}

// Culling receivers by each pass's light frustum only skips pixels whose mask is 0.
TEST(Showroom, CullingReceiversByFrustumKeepsEveryByte) {
  for (const shadow::ProductPose& pose :
       {showroom().startPose, shadow::ProductPose{1, 2.6f, 2.2f, 200.0f, 0.0f},
        shadow::ProductPose{0, 3.0f, 2.4f, 0.0f, 0.3f},
        shadow::ProductPose{2, 1.5f, 3.5f, 45.0f, 0.0f}}) {
    std::vector<std::string> hashes;
    for (bool cull : {true, false}) {
      shadow::CompositorOptions options;
      options.cullReceivers = cull;
      shadow::FrameCompositor compositor(showroom(), options);
      raster::FrameContent frame;
      shadow::CompositeStats stats;
      compositor.compose(pose, 50, 1, frame, stats);
      raster::Renderer renderer(showroom().view, {simd::bestIsa(), 2, 32});
      std::vector<uint8_t> rgba(showroom().background.size());
      renderer.render(frame, rgba);
      hashes.push_back(scene::sha256Hex(rgba));
    }
    EXPECT_EQ(hashes[0], hashes[1]) << "product " << pose.product;
  }
}

// The feedback loop of docs/fig3.md: a frame measures, per receiver vertex, how much of its
// blocked light the passes really occluded; the next frame takes its intensity transfers at
// that share. Deterministic whatever the thread count.
TEST(Showroom, MeasuredOcclusionFeedsTheNextFrame) {
  auto run = [](int threads) {
    shadow::CompositorOptions graded;  // S graded at measured shares: fixed8_8 (u8 alike)
    graded.accumulation = raster::Accumulation::kFixed8_8;
    shadow::FrameCompositor compositor(showroom(), graded);
    raster::Renderer renderer(showroom().view, {simd::bestIsa(), threads, 32});
    raster::FrameContent frame;
    shadow::CompositeStats stats;
    std::vector<uint8_t> rgba(showroom().background.size()), masks;
    const shadow::ProductPose pose{1, 2.5f, 2.0f, 30.0f};
    compositor.compose(pose, 30, 1, frame, stats);
    EXPECT_EQ(stats.gradedVertices, 0u);  // nothing measured yet: Fig. 4
    renderer.render(frame, rgba, compositor.probes(), masks, compositor.objectProbesFrom());
    EXPECT_EQ(masks.size(), compositor.probes().size() * frame.passes.size());
    size_t occluded = 0;
    for (uint8_t m : masks) occluded += m != 0;
    EXPECT_GT(occluded, 0u) << "the bunny must block some light at some receiver vertex";
    compositor.observe(masks);
    compositor.compose(pose, 30, 2, frame, stats);
    // Every receiver vertex, and the product's own vertices (self-shadowing), now graded.
    EXPECT_GT(stats.gradedVertices, stats.receiverVertices);
    renderer.render(frame, rgba, compositor.probes(), masks, compositor.objectProbesFrom());
    return scene::sha256Hex(rgba);
  };
  EXPECT_EQ(run(1), run(3));
}

}  // namespace
}  // namespace penumbra

#ifdef PENUMBRA_HAVE_GLTF
namespace penumbra {
namespace {

namespace fs = std::filesystem;

// A glTF product in a scene file brings its own material (scene/gltf_io.h); "colour" may
// still override the diffuse part.
TEST(Showroom, GltfProductCarriesItsMaterial) {
  const std::string text = R"({
    "format": "penumbra-scene", "version": 1,
    "image": {"width": 64, "height": 48},
    "camera": {"eye": [0.5, 1.5, 0.5], "target": [2, 0.5, 2], "up": [0, 1, 0],
               "fov_y_deg": 60, "near": 0.05, "far": 15},
    "materials": {"wall": {"reflectance": [0.7, 0.7, 0.7]}, "lamp": {"emission": [10, 10, 10]}},
    "room": {"shell": {"min": [0, 0, 0], "max": [4, 3, 4], "floor": "wall", "walls": "wall",
                       "ceiling": "wall"},
             "regions": [{"quad": "ceiling", "name": "l", "u": [1.5, 2.5], "v": [1.5, 2.5],
                          "material": "lamp"}]},
    "patch_size": 0.5, "tone": {"exposure": 1, "gamma": 2.2},
    "products": [{"name": "pot", "model": "../models/teapot.gltf", "proxy_triangles": 200},
                 {"name": "red", "model": "../models/teapot.gltf", "colour": [0.9, 0.1, 0.1],
                  "specular_exponent": 20}],
    "start_pose": {"product": 0, "x": 2, "z": 2, "yaw_deg": 0}
  })";
  const scene::SceneDescription s =
      scene::parseSceneFile(text, fs::path(PENUMBRA_DATA_DIR) / "showroom" / "gltf.json");
  ASSERT_EQ(s.products.size(), 2u);
  EXPECT_NEAR(s.products[0].reflectance.z, 0.62 * 0.751, 0.01);
  EXPECT_NEAR(s.products[0].specular.x, 0.04, 1e-12);
  EXPECT_GT(s.products[0].specularExponent, 100.0);
  EXPECT_EQ(s.products[1].reflectance, glm::dvec3(0.9, 0.1, 0.1));
  EXPECT_EQ(s.products[1].specularExponent, 20.0);
  EXPECT_EQ(s.products[0].mesh.triangleCount(), 992u);
  std::vector<lighting::StageTiming> timings;
  const shadow::SceneBundle b = lighting::precomputeBundle(s, {}, timings);
  EXPECT_NEAR(b.products[0].specular.x, 0.04f, 1e-7);
  EXPECT_FALSE(b.irradiance.empty());
  EXPECT_EQ(timings.back().stage, "irradiance volume");
  EXPECT_EQ(b.patchRadiance.size(), b.patches.size());

  // The specular term (environment map + Phong lobe) brightens the glazed pot, and the
  // frame is the same bytes for any renderer thread count.
  auto compose = [&](bool specular) {
    shadow::CompositorOptions o;
    o.specular = specular;
    shadow::FrameCompositor c(b, o);
    raster::FrameContent frame;
    shadow::CompositeStats stats;
    c.compose({0, 2.0f, 2.0f, 30.0f, 0.0f}, 8, 1, frame, stats);
    return frame;
  };
  const raster::FrameContent with = compose(true), without = compose(false);
  size_t brighter = 0, darker = 0;
  for (size_t v = 0; v < with.objects[0].colours.size(); ++v) {
    const core::Rgb8 a = with.objects[0].colours[v], d = without.objects[0].colours[v];
    brighter += a.r + a.g + a.b > d.r + d.g + d.b;
    darker += a.r < d.r || a.g < d.g || a.b < d.b;
  }
  EXPECT_GT(brighter, with.objects[0].colours.size() / 2);
  EXPECT_EQ(darker, 0u);
  std::vector<std::vector<uint8_t>> frames;
  for (int threads : {1, 2, 3}) {
    raster::Renderer r(b.view, {simd::Isa::kScalar, threads, 32});
    frames.emplace_back(b.background.size());
    r.render(with, frames.back());
  }
  EXPECT_EQ(frames[0], frames[1]);
  EXPECT_EQ(frames[0], frames[2]);
}
}  // namespace
}  // namespace penumbra
#endif
