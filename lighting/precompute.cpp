#include "lighting/precompute.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/json_reader.h"
#include "lighting/embree_scene.h"
#include "lighting/irradiance_volume_gather.h"
#include "lighting/patch_radiosity.h"
#include "lighting/radiance_transfer.h"
#include "raster/renderer.h"
#include "shadow/source_receiver_sets.h"

namespace penumbra::lighting {
namespace {

core::Mesh toRaster(const scene::TriangleMesh& m) {
  core::Mesh out;
  for (const glm::dvec3& p : m.positions) out.positions.push_back(scene::toVec3(p));
  out.indices = m.indices;
  return out;
}

// The background "photograph" of the empty room: every receiver vertex shows T(L_i), the
// radiance the transfers say it reflects (Gouraud between vertices); vertices no camera
// ray reaches stay black. Drawn by the project's own rasterizer as a shaded object over
// black, so it is bit-exact like every frame.
std::vector<uint8_t> renderBackground(const shadow::SceneBundle& b) {
  raster::ShadedMesh room;
  room.mesh = b.view.staticMesh;
  room.colours.assign(room.mesh.positions.size(), core::Rgb8{0, 0, 0});
  const shadow::RadianceTransfers& t = b.transfers;
  for (size_t i = 0; i < t.receiverVertices.size(); ++i) {
    room.colours[t.receiverVertices[i]] = b.tone.map(glm::dvec3(t.vertexRadiance[i]));
  }
  raster::FrameContent frame;
  frame.background.assign(size_t{b.view.width} * b.view.height * 4, 0);
  for (size_t i = 3; i < frame.background.size(); i += 4) frame.background[i] = 255;
  frame.objects.push_back(std::move(room));
  raster::StaticView empty{b.view.width, b.view.height, b.view.cameraViewProj, {}};
  raster::Renderer renderer(empty, {simd::bestIsa(), 2, 32});
  std::vector<uint8_t> out(frame.background.size());
  renderer.render(frame, out);
  return out;
}

}  // namespace

glm::uvec3 scaledVolumeDims(double scale) {
  if (!(scale > 0 && scale <= 8)) {
    throw std::invalid_argument("volume scale " + core::formatNumber(scale) + " is not in (0, 8]");
  }
  const glm::uvec3 dims = PrecomputeOptions{}.volumeDims;
  glm::uvec3 out;
  for (int k = 0; k < 3; ++k) {
    out[k] = static_cast<unsigned>(std::max<long long>(1, std::llround(double(dims[k]) * scale)));
  }
  return out;
}

scene::PatchMesh precomputePatchMesh(const scene::SceneDescription& scene,
                                     const PrecomputeOptions& options) {
  const double e = options.emitterPatchSize;
  if (!(e == 0 || (e >= scene::kMinPatchSize && e <= scene::kMaxPatchSize))) {
    throw scene::SceneFileError(scene.source.string(),
                                "emitter patch size " + core::formatNumber(e),
                                "is not in [" + core::formatNumber(scene::kMinPatchSize) + ", " +
                                    core::formatNumber(scene::kMaxPatchSize) + "] metres");
  }
  const double size = options.patchSize > 0 ? options.patchSize : scene.patchSize;
  // A patch-size override refines the whole room, emitters' own regions included (more,
  // smaller sources: the fine end of the speed/accuracy trade-off); an emitter override only
  // the emitting regions and quads.
  scene::RoomDescription room = scene.room;
  for (scene::Quad& q : room.quads) {
    for (scene::Region& r : q.regions) {
      if (options.patchSize > 0) r.patchSize = std::min(r.patchSize, options.patchSize);
      // A region's 0 means the mesh's size, which may be finer already.
      if (e > 0 && r.material.emits()) {
        r.patchSize = std::min(r.patchSize > 0 ? r.patchSize : size, e);
      }
    }
    if (e > 0 && q.material.emits()) q.refinements.push_back({0, 1, 0, 1, e});
  }
  // The scene file checked its own patch size (scene_file.h); an override is checked here.
  if (const double patches = scene::patchCount(room, size); patches > scene::kMaxPatches) {
    std::string sizes = "patch size " + core::formatNumber(size);
    if (e > 0) sizes += ", emitters " + core::formatNumber(e);
    throw scene::SceneFileError(scene.source.string(), sizes,
                                "cuts the room into " + core::formatNumber(patches) +
                                    " patches, more than the " +
                                    core::formatNumber(scene::kMaxPatches) + " precompute handles");
  }
  try {
    return scene::buildPatchMesh(room, size, scene::kMaxPatches);
  } catch (const std::length_error&) {
    // Only shadow-boundary refinement grows past the count checked above.
    throw scene::SceneFileError(
        scene.source.string(), "shadow_boundary_patch_size",
        core::formatNumber(room.shadowBoundaryPatchSize) +
            " m refines the room into more than the " + core::formatNumber(scene::kMaxPatches) +
            " patches precompute handles: use a larger shadow_boundary_patch_size");
  }
}

shadow::SceneBundle precomputeBundle(const scene::SceneDescription& scene,
                                     const PrecomputeOptions& options,
                                     std::vector<StageTiming>& timings,
                                     const ProgressCallback& progress) {
  const int kStages = options.irradianceVolume ? 6 : 5;
  int stage = 0;
  auto start = std::chrono::steady_clock::now();
  auto begin = [&](const char* name) {
    start = std::chrono::steady_clock::now();
    if (progress) progress(name, stage, kStages);
    timings.push_back({name, 0});
    ++stage;
  };
  auto end = [&] {
    timings.back().ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };

  shadow::SceneBundle b;
  begin("patch mesh");
  scene::PatchMesh mesh = precomputePatchMesh(scene, options);
  if (!options.measuredMaterials.empty()) {
    if (options.measuredMaterials.size() != mesh.patches.size()) {
      throw std::invalid_argument(
          "precompute: " + std::to_string(options.measuredMaterials.size()) +
          " measured materials for a mesh of " + std::to_string(mesh.patches.size()) + " patches");
    }
    for (size_t i = 0; i < mesh.patches.size(); ++i) {
      mesh.patches[i].reflectance = options.measuredMaterials[i].reflectance;
      mesh.patches[i].emission = options.measuredMaterials[i].emission;
    }
  }
  if (!options.measuredRadiance.empty() && options.measuredRadiance.size() != mesh.patches.size()) {
    throw std::invalid_argument("precompute: measured radiance needs one value per patch (" +
                                std::to_string(mesh.patches.size()) + ")");
  }
  b.view.width = scene.width;
  b.view.height = scene.height;
  b.view.cameraViewProj = scene.camera.rasterViewProj();
  b.view.staticMesh = mesh.toRasterMesh();
  b.trianglePatch = mesh.trianglePatch;
  for (const scene::Patch& p : mesh.patches) {
    b.patches.push_back({glm::vec3(p.centre), glm::vec3(p.normal), static_cast<float>(p.area),
                         glm::vec3(p.reflectance), glm::vec3(p.emission), p.firstTriangle});
  }
  b.tone = options.tone ? *options.tone
                        : shadow::ToneCurve::gamma(scene.tone.exposure, scene.tone.gamma);
  if (!options.background.empty() &&
      options.background.size() != size_t{scene.width} * scene.height * 4) {
    throw std::invalid_argument("precompute: the background photograph is not " +
                                std::to_string(scene.width) + "x" + std::to_string(scene.height) +
                                " RGBA8");
  }
  end();

  // Everything downstream is computed from the bundle's own (float) mesh, exactly what
  // `penumbra render` rebuilds at load.
  const scene::PatchMesh stored = shadow::patchMeshOf(b);
  begin("visibility and sets");
  const EmbreeScene embree(stored);
  const std::vector<uint8_t> visible =
      patchesVisibleFromCamera(stored, embree, scene.camera.viewProj(), scene.width, scene.height);
  b.sets = shadow::selectSourcesAndReceivers(
      stored, visible, options.powerShare > 0 ? options.powerShare : scene.powerShare);
  // A bundle without receivers has nothing to shade: `render` and the kiosk refuse it
  // (shadow/scene_bundle.h), so precompute refuses to write it (issue 18: it printed
  // "receivers 0", exited 0, and the kiosk then crashed on the bundle).
  if (b.sets.receivers.empty()) {
    throw scene::SceneFileError(scene.source.string(), "camera",
                                "sees no surface of the room (0 receivers): aim camera.target "
                                "at the room");
  }
  end();

  begin("radiance transfers");
  TransferOptions transferOptions;
  transferOptions.samplesPerSide = options.samplesPerSide;
  transferOptions.seed = options.seed;
  transferOptions.threads = options.threads;
  b.transfers = computeRadianceTransfers(stored, b.sets, embree, transferOptions);
  end();

  begin("background");
  b.background = options.background.empty() ? renderBackground(b) : options.background;
  end();

  begin("products");
  for (const scene::Product& p : scene.products) {
    shadow::ProductModel m;
    m.name = p.name;
    m.mesh = toRaster(p.mesh);
    m.proxy = toRaster(p.proxy);
    m.fineProxy = toRaster(p.fineProxy);
    for (const glm::dvec3& n : p.mesh.normals) m.normals.push_back(glm::vec3(n));
    for (const glm::dvec3& r : p.mesh.reflectances) m.reflectances.push_back(glm::vec3(r));
    m.reflectance = glm::vec3(p.reflectance);
    m.specular = glm::vec3(p.specular);
    m.specularExponent = static_cast<float>(p.specularExponent);
    b.products.push_back(std::move(m));
  }
  // Each product's fine-proxy passes when any product states its own (the rest keep the
  // default), so a bundle whose scene names none stays as before.
  if (std::any_of(scene.products.begin(), scene.products.end(),
                  [](const scene::Product& p) { return p.fineProxyPasses.has_value(); })) {
    for (const scene::Product& p : scene.products) {
      b.settings.productFineProxyPasses.push_back(
          p.fineProxyPasses.value_or(b.settings.fineProxyPasses));
    }
  }
  b.startPose = {static_cast<uint32_t>(scene.startPose.product),
                 static_cast<float>(scene.startPose.x), static_cast<float>(scene.startPose.z),
                 static_cast<float>(scene.startPose.yawDegrees)};
  end();

  if (options.irradianceVolume) {
    // Gibson & Chalmers 2003 §5: the products' diffuse light, gathered from every patch.
    begin("irradiance volume");
    GatherOptions gather;
    gather.threads = options.threads;
    const std::vector<glm::dvec3> radiance =
        options.measuredRadiance.empty()
            ? solvePatchRadiance(stored, embree, options.radianceBounces, gather)
            : options.measuredRadiance;
    IrradianceVolumeOptions volume;
    volume.dims = options.volumeDims;
    volume.directionsPerSide = options.volumeDirectionsPerSide;
    volume.threads = options.threads;
    volume.seed = options.seed ^ 0x4952524144564F4Cull;
    b.irradiance = buildIrradianceVolume(stored, embree, radiance, volume);
    for (const glm::dvec3& l : radiance) b.patchRadiance.emplace_back(glm::max(l, glm::dvec3(0.0)));
    end();
  }
  return b;
}

}  // namespace penumbra::lighting
