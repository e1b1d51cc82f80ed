// Scene bundles: exact round trip, and damaged bundles refused with the section named.
#include "shadow/scene_bundle.h"

#include <gtest/gtest.h>

#include <cmath>

#include <cstring>
#include <fstream>
#include <iterator>
#include <span>

#include "scene/bundle_io.h"
#include "scene/sha256.h"

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
  core::Mesh proxy = b.view.staticMesh;
  proxy.indices.resize(3);  // one triangle; the fine proxy is the whole quad
  ProductModel chair{"chair", b.view.staticMesh, proxy, b.view.staticMesh, {0.3f, 0.2f, 0.1f}};
  b.products = {chair, ProductModel{"lamp", b.view.staticMesh, proxy, {}, {}}};
  b.startPose = {1, 0.5f, -0.25f, 30.0f};
  return b;
}

fs::path tempPath(const char* name) {
  return fs::temp_directory_path() / name;
}

// Saves `b` to `path` and loads it back: the refusal's message, or "accepted".
std::string refusalOf(const SceneBundle& b, const fs::path& path) {
  saveBundle(b, path);
  try {
    loadBundle(path);
  } catch (const scene::BundleError& e) {
    return e.what();
  }
  return "accepted";
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
  EXPECT_EQ(r.products[0].fineProxy, b.products[0].fineProxy);
  EXPECT_TRUE(r.products[1].fineProxy.indices.empty());
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

// v7: the render settings round-trip, and a bundle carrying unusable ones is refused with
// the setting named (v8: with the shaft pruning fraction and receivers per leaf; v10: the
// texels per shadow pixel).
TEST(SceneBundle, RenderSettingsRoundTripAndAreValidated) {
  const fs::path path = tempPath("penumbra-scene-bundle-settings.bundle");
  SceneBundle b = smallBundle();
  EXPECT_EQ(b.settings, RenderSettings{});
  b.settings = {24, 128, 8, false, true, 0.05, 4, {50, 0}, 0.75};
  saveBundle(b, path);
  EXPECT_EQ(loadBundle(path).settings, b.settings);
  b.settings.productFineProxyPasses.clear();
  saveBundle(b, path);
  EXPECT_EQ(loadBundle(path).settings, b.settings);
  const auto refusal = [&](const RenderSettings& s) {
    b.settings = s;
    return refusalOf(b, path);
  };
  EXPECT_EQ(refusal({0, 256, 16, true, false}),
            path.string() + ": section 'settings': settings.max_passes: 0 is not in [1, 257]");
  EXPECT_EQ(refusal({64, 200, 16, true, false}),
            path.string() +
                ": section 'settings': settings.shadow_map_size: 200 is not a multiple of 16 in "
                "[64, 4096]");
  EXPECT_EQ(
      refusal({64, 256, 300, true, false}),
      path.string() + ": section 'settings': settings.fine_proxy_passes: 300 is more than 257");
  EXPECT_EQ(
      refusal({64, 256, 16, true, false, 0.3, 8}),
      path.string() + ": section 'settings': settings.prune_fraction: 0.3 is not in [0, 0.25]");
  EXPECT_EQ(
      refusal({64, 256, 16, true, false, 0.02, 0}),
      path.string() + ": section 'settings': settings.receivers_per_leaf: 0 is not in [1, 64]");
  EXPECT_EQ(
      refusal({64, 256, 16, true, false, 0.02, 8, {16, 258}}),
      path.string() +
          ": section 'settings': settings.product_fine_proxy_passes[1]: 258 is more than 257");
  EXPECT_EQ(
      refusal({64, 256, 16, true, false, 0.02, 8, {16, 16, 16}}),
      path.string() +
          ": section 'settings': settings.product_fine_proxy_passes: 3 values for 2 products");
  EXPECT_EQ(refusal({64, 256, 16, true, false, 0.02, 8, {}, 65}),
            path.string() +
                ": section 'settings': settings.texels_per_shadow_pixel: 65 is not in [0, 64]");
  EXPECT_EQ(refusal({64, 256, 16, true, false, 0.02, 8, {}, std::nan("")}),
            path.string() +
                ": section 'settings': settings.texels_per_shadow_pixel: nan is not in [0, 64]");
  fs::remove(path);
}

// Issue 18: a bundle whose camera sees no receiver, or without a room, made `render` and
// the kiosk segfault while building the compositor. Refused at load, as precompute refuses
// to write it, so the kiosk falls back to its last good bundle.
TEST(SceneBundle, BundleWithNothingToShadeIsRefused) {
  const fs::path path = tempPath("penumbra-scene-bundle-empty.bundle");
  const auto refusal = [&](const SceneBundle& b) { return refusalOf(b, path); };
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

namespace penumbra::shadow {
namespace {

// v5: the products' per-vertex normals and reflectances.
TEST(SceneBundle, PerVertexNormalsAndReflectancesRoundTripAndAreValidated) {
  SceneBundle b = smallBundle();
  b.products[0].normals = {{0, 1, 0}, {0, 1, 0}, {0.6f, 0.8f, 0}, {0, 0, 1}};
  b.products[0].reflectances = {{0.1f, 0.2f, 0.3f}, {1, 1, 1}, {0, 0, 0}, {0.5f, 0.5f, 0.5f}};
  const fs::path path = tempPath("penumbra-scene-bundle-v5.bundle");
  saveBundle(b, path);
  const SceneBundle r = loadBundle(path);
  EXPECT_EQ(r.products[0].normals, b.products[0].normals);
  EXPECT_EQ(r.products[0].reflectances, b.products[0].reflectances);
  EXPECT_TRUE(r.products[1].normals.empty());
  EXPECT_TRUE(r.products[1].reflectances.empty());

  auto refusal = [&](const SceneBundle& bad) {
    saveBundle(bad, path);
    try {
      loadBundle(path);
    } catch (const scene::BundleError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  SceneBundle bad = b;
  bad.products[0].normals.pop_back();
  EXPECT_EQ(refusal(bad),
            path.string() + ": section 'products.0.normals': 3 normals for 4 vertices");
  bad = b;
  bad.products[0].normals[1] = {0, 2, 0};
  EXPECT_EQ(refusal(bad),
            path.string() + ": section 'products.0.normals': normal 1 is not of unit length");
  bad = b;
  bad.products[0].normals[2].x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(refusal(bad).find("normal 2 is not of unit length"), std::string::npos);
  bad = b;
  bad.products[0].reflectances.push_back({0, 0, 0});
  EXPECT_NE(refusal(bad).find("'products.0.reflectances': 5 reflectances for 4 vertices"),
            std::string::npos);
  bad = b;
  bad.products[0].reflectances[3].z = 1.5f;
  EXPECT_EQ(refusal(bad),
            path.string() + ": section 'products.0.reflectances': reflectance 3 is not in [0, 1]");
  fs::remove(path);
}

// The bundle container's sections (scene/bundle_io.h layout), to rewrite a bundle as an older
// version would have written it.
struct RawSection {
  std::string name;
  uint32_t elementSize;
  uint64_t count;
  std::string data;
};

std::vector<RawSection> readSections(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  uint32_t count;
  std::memcpy(&count, bytes.data() + 20, 4);
  std::vector<RawSection> out;
  size_t at = 56;
  for (uint32_t s = 0; s < count; ++s) {
    RawSection r;
    uint32_t nameLength;
    std::memcpy(&nameLength, bytes.data() + at, 4);
    r.name = bytes.substr(at + 4, nameLength);
    at += 4 + nameLength;
    std::memcpy(&r.elementSize, bytes.data() + at, 4);
    std::memcpy(&r.count, bytes.data() + at + 4, 8);
    at += 12;
    r.data = bytes.substr(at, r.elementSize * r.count);
    at += r.data.size();
    out.push_back(std::move(r));
  }
  return out;
}

// Version 4 and 5 bundles still load: a version 4 bundle (before per-vertex normals and
// reflectances) has neither, and shades with area-weighted normals and its one reflectance;
// neither has fine proxies (version 6), so every pass draws the proxy. Before version 7 the
// settings are the defaults; a version 7 bundle keeps its own but the shaft settings of
// version 8, a version 8 one the per-product fine-proxy passes of version 9, and a version 9
// one the map per cluster of version 10.
TEST(SceneBundle, Version4To9BundlesStillLoad) {
  SceneBundle b = smallBundle();
  b.products[0].normals.assign(4, {0, 1, 0});
  // Not the defaults, which the older versions must load with.
  b.settings.maxPasses = 12;
  b.settings.pruneFraction = 0.05;
  b.settings.receiversPerLeaf = 4;
  b.settings.productFineProxyPasses = {4, 30};
  b.settings.texelsPerShadowPixel = 1.5;
  const fs::path path = tempPath("penumbra-scene-bundle-old-compat.bundle");
  for (const uint32_t version : {4u, 5u, 6u, 7u, 8u, 9u}) {
    saveBundle(b, path);
    // Rewritten as `version`: the same sections without the newer ones, rehashed.
    const auto newer = [&](const std::string& name) {
      if (name == "settings.texels_per_shadow_pixel") return true;
      if (version < 9 && name == "settings.product_fine_proxy_passes") return true;
      if (version < 8 &&
          (name == "settings.prune_fraction" || name == "settings.receivers_per_leaf")) {
        return true;
      }
      if (version < 7 && name.starts_with("settings.")) return true;
      if (version < 6 && name.find(".fine_proxy.") != std::string::npos) return true;
      return version < 5 && (name.ends_with(".normals") || name.ends_with(".reflectances"));
    };
    std::string body;
    uint32_t kept = 0, dropped = 0;
    const auto put = [&](const auto& v) {
      body.append(reinterpret_cast<const char*>(&v), sizeof(v));
    };
    for (const RawSection& sec : readSections(path)) {
      if (newer(sec.name)) {
        ++dropped;
        continue;
      }
      put(static_cast<uint32_t>(sec.name.size()));
      body += sec.name;
      put(sec.elementSize);
      put(sec.count);
      body += sec.data;
      ++kept;
    }
    // The texels per shadow pixel, before version 9 the per-product fine-proxy passes, before
    // version 8 the two shaft settings, before 7 the five others; before version 6 the two
    // products' fine proxies (positions and indices), before 5 also their normals and
    // reflectances.
    EXPECT_EQ(dropped, 1u + (version < 9 ? 1u : 0u) + (version < 8 ? 2u : 0u) +
                           (version < 7 ? 5u : 0u) + (version < 6 ? 4u : 0u) +
                           (version < 5 ? 4u : 0u))
        << version;
    scene::Sha256 hash;
    hash.update(std::span(reinterpret_cast<const uint8_t*>(body.data()), body.size()));
    const auto digest = hash.finish();
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write("PENUMBRA-BUNDLE", 16);
      out.write(reinterpret_cast<const char*>(&version), 4);
      out.write(reinterpret_cast<const char*>(&kept), 4);
      out.write(reinterpret_cast<const char*>(digest.data()), std::streamsize(digest.size()));
      out << body;
    }
    const SceneBundle r = loadBundle(path);
    ASSERT_EQ(r.products.size(), 2u);
    EXPECT_EQ(r.products[0].normals.empty(), version < 5) << version;
    EXPECT_TRUE(r.products[0].reflectances.empty());
    EXPECT_EQ(r.products[0].fineProxy.indices.empty(), version < 6) << version;
    RenderSettings expected;
    if (version >= 7) expected.maxPasses = 12;
    if (version >= 8) {
      expected.pruneFraction = 0.05;
      expected.receiversPerLeaf = 4;
    }
    if (version == 9) expected.productFineProxyPasses = {4, 30};
    EXPECT_EQ(r.settings, expected) << version;
    EXPECT_EQ(r.products[0].mesh, b.products[0].mesh);
    EXPECT_EQ(r.products[0].proxy, b.products[0].proxy);
    EXPECT_EQ(r.products[0].reflectance, b.products[0].reflectance);
  }
  // Version 3 is refused, naming both ends of what is read.
  scene::BundleWriter v3(3);
  v3.write(path);
  try {
    loadBundle(path);
    ADD_FAILURE() << "accepted version 3";
  } catch (const scene::BundleError& e) {
    EXPECT_NE(std::string(e.what()).find("version 3, this program reads version 4 to " +
                                         std::to_string(kBundleVersion)),
              std::string::npos)
        << e.what();
  }
  fs::remove(path);
}

}  // namespace
}  // namespace penumbra::shadow
