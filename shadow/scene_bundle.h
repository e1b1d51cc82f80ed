// Everything `penumbra precompute` derives from a showroom once, as one checksummed file
// (scene/bundle_io.h) that `penumbra render` and the kiosk load in milliseconds: the
// calibrated view and its background photograph, the room's patch mesh, the camera
// response T(), the light transport of Gibson 2003 §4–5, and the products.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/intensity_transfer.h"
#include "shadow/irradiance_volume.h"
#include "shadow/light_transport.h"
#include "shadow/render_settings.h"

namespace penumbra::shadow {

// 4: the irradiance volume (Gibson & Chalmers 2003 §5) and the products' specular terms.
// 5: the products' per-vertex normals and reflectances (issue 15 item 6). Version 4 bundles
// still load: their products have neither (area-weighted normals, one reflectance).
// 6: the products' fine shadow proxies (`fine_proxy_triangles`); older bundles load without.
// 7: the render settings (shadow/render_settings.h); older bundles load with the defaults.
// 8: the settings' shaft pruning fraction and receivers per leaf; version 7 bundles load
// with their defaults.
// 9: the settings' fine-proxy passes per product; older bundles give every product the same.
// 10: the settings' texels per shadow pixel (a map size per cluster); older bundles give every
// pass the frame's map.
inline constexpr uint32_t kBundleVersion = 10;
inline constexpr uint32_t kOldestBundleVersion = 4;

// A patch as the per-frame pipeline needs it (scene::Patch in float).
struct PatchRecord {
  glm::vec3 centre, normal;
  float area;
  glm::vec3 reflectance, emission;
  uint32_t firstTriangle;  // triangles firstTriangle and firstTriangle + 1
};

// A product: its display mesh (standing on y = 0, centred on the origin at yaw 0), its
// shadow proxy of 100–500 triangles (Gibson 2003 §7.2, positions only), a diffuse reflectance
// and a Phong-like specular lobe (Gibson & Chalmers 2003 §5; strength 0 = purely diffuse).
// Per mesh vertex, optionally: the model's normals (as exported, or split by smoothing group
// or crease angle: scene/mesh_attributes.h) and diffuse reflectances (OBJ materials, glTF base
// colour and textures). Without normals the shading sums area-weighted face normals; without
// reflectances every vertex has `reflectance`.
struct ProductModel {
  std::string name;
  core::Mesh mesh;
  core::Mesh proxy;
  // A finer proxy, or empty: the frame's most energetic passes draw it instead of `proxy`
  // (PassListOptions::fineProxyPasses), where a light carries enough of a contact shadow
  // for the coarse proxy's feet and base to show.
  core::Mesh fineProxy;
  glm::vec3 reflectance{0.6f};
  glm::vec3 specular{0.0f};               // specular reflectance per channel, in [0, 1]
  float specularExponent = 0.0f;          // Phong exponent of the lobe, >= 0
  std::vector<glm::vec3> normals{};       // empty or one unit vector per mesh vertex
  std::vector<glm::vec3> reflectances{};  // empty or one per mesh vertex, each channel in [0, 1]
};

// Where a product stands: at (x, z) on the floor, `lift` above it, turned by yaw about +y.
struct ProductPose {
  uint32_t product = 0;
  float x = 0, z = 0, yawDegrees = 0;
  float lift = 0;  // metres above the floor (Gibson 2003 Fig. 7: lifting a box off the floor)
};

// `in` (product space) moved to `pose`: turned by yawDegrees about +y (portable
// sin/cos, scene/portable_trig.h), lifted, moved to (x, z), rounded to float. The one
// placement shared by the per-frame compositor and the ray-traced reference, so both see
// the product in the same place to the bit. The pose's product index is not used.
void placeMesh(const core::Mesh& in, const ProductPose& pose, core::Mesh& out);
// Normals turned by the pose's yaw as placeMesh turns positions (the same portable sine and
// cosine, in double, rounded to float).
void placeNormals(const std::vector<glm::vec3>& in, const ProductPose& pose,
                  std::vector<glm::vec3>& out);
// The normals product `model` is shaded with, placed by `pose`: its own (placeNormals), or
// without them the area-weighted sums of the placed mesh's face normals (not normalized,
// shadow/irradiance_volume.h vertexNormals). The per-frame shading and the ray-traced
// reference both take them from here.
std::vector<glm::vec3> shadingNormals(const ProductModel& model, const core::Mesh& placed,
                                      const ProductPose& pose);

struct SceneBundle {
  raster::StaticView view;              // image size, camera, the room's triangles
  std::vector<uint8_t> background;      // RGBA8 "photograph" of the empty room
  std::vector<uint32_t> trianglePatch;  // per static triangle: index into patches
  std::vector<PatchRecord> patches;
  ToneCurve tone;
  SourceReceiverSets sets;
  RadianceTransfers transfers;
  std::vector<ProductModel> products;
  ProductPose startPose;
  // Diffuse light for the products (§5); empty: shaded by the emitters' form factors.
  IrradianceVolume irradiance;
  // Outgoing radiance per patch (what the volume was gathered from): the room as the
  // products' specular environment maps show it. Empty: no specular term.
  std::vector<glm::vec3> patchRadiance;
  // How its frames are drawn: the defaults, or what `penumbra tune` chose for this scene.
  RenderSettings settings;
};

// The room's patch mesh as stored in the bundle (float data widened to double): what the
// shaft hierarchy is built from at load, so precompute and render agree exactly.
scene::PatchMesh patchMeshOf(const SceneBundle& bundle);

// Throws scene::BundleError naming the file.
void saveBundle(const SceneBundle& bundle, const std::filesystem::path& path);
// Reads and validates (sizes, indices, finite numbers); throws scene::BundleError naming
// the file and the section.
SceneBundle loadBundle(const std::filesystem::path& path);

}  // namespace penumbra::shadow
