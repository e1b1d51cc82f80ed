// Scene bundles: exact round trip, and damaged bundles refused with the section named.
#include "shadow/scene_bundle.h"

#include <gtest/gtest.h>

#include "scene/bundle_io.h"

namespace penumbra::shadow {
namespace {

namespace fs = std::filesystem;

SceneBundle smallBundle() {
  SceneBundle b;
  b.view.width = 4;
  b.view.height = 2;
  b.view.cameraViewProj = raster::Mat4::identity();
  b.view.staticMesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  b.view.staticMesh.indices = {0, 1, 2, 0, 2, 3};
  b.background.assign(4 * 2 * 4, 77);
  b.trianglePatch = {0, 0};
  b.patches.push_back({{0.5f, 0, 0.5f}, {0, 1, 0}, 1.0f, {0.5f, 0.5f, 0.5f}, {2, 2, 2}, 0});
  b.tone = ToneCurve::gamma(1.0);
  b.sets.sources = {0};
  b.sets.receivers = {0};
  b.transfers.receiverVertices = {0, 1, 2, 3};
  b.transfers.vertexRadiance = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  b.transfers.sourceStart = {0, 2};
  b.transfers.entryVertex = {1, 3};
  b.transfers.entryTransfer = {{0.5f, 0.5f, 0.5f}, {0.25f, 0.25f, 0.25f}};
  b.transfers.sourceAverage = {0.2f};
  ProductModel chair{"chair", b.view.staticMesh, b.view.staticMesh, {0.3f, 0.2f, 0.1f}};
  b.products = {chair, ProductModel{"lamp", b.view.staticMesh, b.view.staticMesh, {}}};
  b.startPose = {1, 0.5f, -0.25f, 30.0f};
  return b;
}

fs::path tempPath(const char* name) {
  return fs::temp_directory_path() / name;
}

TEST(SceneBundle, RoundTripIsExact) {
  const SceneBundle b = smallBundle();
  const fs::path path = tempPath("penumbra-scene-bundle-roundtrip.bundle");
  saveBundle(b, path);
  const SceneBundle r = loadBundle(path);
  EXPECT_EQ(r.view, b.view);
  EXPECT_EQ(r.background, b.background);
  EXPECT_EQ(r.trianglePatch, b.trianglePatch);
  EXPECT_EQ(r.tone.thresholds(), b.tone.thresholds());
  EXPECT_EQ(r.sets.sources, b.sets.sources);
  EXPECT_EQ(r.transfers.entryTransfer, b.transfers.entryTransfer);
  EXPECT_EQ(r.transfers.sourceStart, b.transfers.sourceStart);
  ASSERT_EQ(r.products.size(), 2u);
  EXPECT_EQ(r.products[1].name, "lamp");
  EXPECT_EQ(r.products[0].proxy, b.products[0].proxy);
  EXPECT_EQ(r.startPose.product, 1u);
  EXPECT_EQ(r.startPose.yawDegrees, 30.0f);
  fs::remove(path);
}

TEST(SceneBundle, InconsistentContentIsNamed) {
  SceneBundle b = smallBundle();
  b.transfers.entryVertex[1] = 9;  // receiver vertex out of range
  const fs::path path = tempPath("penumbra-scene-bundle-bad.bundle");
  saveBundle(b, path);
  try {
    loadBundle(path);
    FAIL() << "accepted an out-of-range receiver vertex";
  } catch (const scene::BundleError& e) {
    EXPECT_NE(std::string(e.what()).find("transfers.entry_vertex"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  b = smallBundle();
  b.startPose.product = 5;
  saveBundle(b, path);
  EXPECT_THROW(loadBundle(path), scene::BundleError);
  fs::remove(path);
}

}  // namespace
}  // namespace penumbra::shadow
