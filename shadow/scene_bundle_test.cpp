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
  b.view.cameraViewProj = core::Mat4::identity();
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

// Issue 18: a bundle whose camera sees no receiver, or without a room, made `render` and
// the kiosk segfault while building the compositor. Refused at load, as precompute refuses
// to write it, so the kiosk falls back to its last good bundle.
TEST(SceneBundle, BundleWithNothingToShadeIsRefused) {
  const fs::path path = tempPath("penumbra-scene-bundle-empty.bundle");
  const auto refusal = [&](const SceneBundle& b) -> std::string {
    saveBundle(b, path);
    try {
      loadBundle(path);
    } catch (const scene::BundleError& e) {
      return e.what();
    }
    return "accepted";
  };
  SceneBundle b = smallBundle();
  b.sets.receivers.clear();
  EXPECT_EQ(
      refusal(b),
      path.string() + ": section 'sets.receivers': none (the camera sees no surface of the room)");
  b = smallBundle();
  b.view.staticMesh.indices.clear();
  b.trianglePatch.clear();
  EXPECT_EQ(refusal(b),
            path.string() + ": section 'view.static_mesh': no triangles (a bundle needs a room)");
  fs::remove(path);
}

// v4: the irradiance volume, per-patch radiance and the products' specular terms.
TEST(SceneBundle, IrradianceVolumeAndSpecularRoundTripAndAreValidated) {
  SceneBundle b = smallBundle();
  b.irradiance.dims = {2, 1, 3};
  b.irradiance.origin = {0.1f, 0.2f, 0.3f};
  b.irradiance.spacing = {0.5f, 1.0f, 0.25f};
  for (size_t i = 0; i < 6 * kShFloats; ++i) b.irradiance.coefficients.push_back(float(i) * 0.5f);
  b.irradiance.valid = {1, 1, 0, 1, 1, 1};
  b.irradiance.fallback[3] = 2.5f;
  b.patchRadiance = {{1.5f, 2.0f, 0.25f}};
  b.products[0].specular = {0.04f, 0.04f, 0.04f};
  b.products[0].specularExponent = 131.0f;
  const fs::path path = tempPath("penumbra-scene-bundle-v4.bundle");
  saveBundle(b, path);
  const SceneBundle r = loadBundle(path);
  EXPECT_EQ(r.irradiance.dims, b.irradiance.dims);
  EXPECT_EQ(r.irradiance.origin, b.irradiance.origin);
  EXPECT_EQ(r.irradiance.coefficients, b.irradiance.coefficients);
  EXPECT_EQ(r.irradiance.valid, b.irradiance.valid);
  EXPECT_EQ(r.irradiance.fallback, b.irradiance.fallback);
  EXPECT_EQ(r.patchRadiance, b.patchRadiance);
  EXPECT_EQ(r.products[0].specular, b.products[0].specular);
  EXPECT_EQ(r.products[0].specularExponent, 131.0f);

  auto expectRefused = [&](SceneBundle bad, const std::string& section) {
    saveBundle(bad, path);
    try {
      loadBundle(path);
      ADD_FAILURE() << "accepted a bad " << section;
    } catch (const scene::BundleError& e) {
      EXPECT_NE(std::string(e.what()).find(section), std::string::npos) << e.what();
    }
  };
  SceneBundle bad = b;
  bad.irradiance.coefficients.pop_back();
  expectRefused(bad, "irradiance");
  bad = b;
  bad.irradiance.coefficients[7] = std::numeric_limits<float>::quiet_NaN();
  expectRefused(bad, "irradiance");
  bad = b;
  bad.irradiance.dims = {4096, 4096, 4096};
  expectRefused(bad, "irradiance.dims");
  bad = b;
  bad.irradiance.spacing.x = -1.0f;
  expectRefused(bad, "irradiance");
  bad = b;
  bad.patchRadiance.push_back({1, 1, 1});
  expectRefused(bad, "patch_radiance");
  bad = b;
  bad.patchRadiance[0].y = -1.0f;
  expectRefused(bad, "patch_radiance");
  bad = b;
  bad.products[0].specular.x = 2.0f;
  expectRefused(bad, "products.0.specular");
  bad = b;
  bad.products[0].specularExponent = std::numeric_limits<float>::infinity();
  expectRefused(bad, "products.0.specular_exponent");
  fs::remove(path);
}

}  // namespace
}  // namespace penumbra::shadow
