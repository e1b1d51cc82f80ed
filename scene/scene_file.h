// The showroom scene file read by `penumbra precompute SCENE -o BUNDLE`: one JSON
// document describing the real room (as a RoomDescription: shell, quads, solid boxes,
// lit regions), the kiosk camera, the image size, the patch size of the radiosity mesh
// (Gibson 2003 §4), the display tone curve and the virtual products with their occluder
// proxies (§7.2). data/showroom/showroom.json is the reference example and
// data/showroom/README.md documents every field.
//
// Loading is strict: a missing or unknown field, a wrong type, an out-of-range number or
// an unreadable model throws SceneFileError naming the file and the JSON field (e.g.
// "showroom.json: products[1].scale: must be positive"), because a scene is edited by
// hand and a silently defaulted typo would only show up as a wrong shadow.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "scene/camera.h"
#include "scene/mesh_io.h"
#include "scene/patch_mesh.h"

namespace penumbra::scene {

class SceneFileError : public core::Error {
 public:
  using core::Error::Error;
};

// Limits by design (docs/input-limits.md, "Scene files"). A scene is typed by a technician,
// and a typo must get a message naming the field, not an Embree assertion, a precompute
// that runs for hours or one that exhausts memory (issue 18):
//
// Every room point (shell and box corners, quad corners) lies within ±100 m of the origin:
// a showroom, a shop floor or a hall, measured in metres from a corner of it.
constexpr double kMaxRoomCoordinate = 100;
// Every box axis and quad edge measures at least 1 cm: smaller is a typo, and a shell 5e-324 m
// high passed "max exceeds min" only to give faces whose area rounds to zero (fuzzing found
// it: std::invalid_argument escaped the parser).
constexpr double kMinRoomExtent = 0.01;
// Patch sizes (patch_size, regions' patch_size) in metres, as `precompute --patch-size`.
constexpr double kMinPatchSize = 0.02, kMaxPatchSize = 10;
// The room's patch count (Gibson 2003 §4) bounds precompute's time and memory: sources x
// receivers visibility rays and transfer entries grow with its square. Measured (2 threads):
// the bundled 6 x 3 x 5 m showroom, 1,118 patches, 1.3 s and 72 MB; a 34 x 3 x 34 m hall at
// 0.4 m with an all-emitting ceiling, 18,298 patches (7,969 sources), 93 s and 600 MB. A
// larger room needs a larger patch_size.
constexpr double kMaxPatches = 20000;
// The camera's eye lies within 10 m of the room's bounding box (a kiosk camera looks at
// the room from inside it or through its open side), and its far plane within 1 km.
constexpr double kMaxCameraDistanceFromRoom = 10;
constexpr double kMinCameraNear = 1e-3, kMaxCameraFar = 1000;
// Emitted radiance per channel: a bright ceiling panel is tens; above a million is a typo.
constexpr double kMaxEmission = 1e6;
// Regions per quad (their overlap check is quadratic) and products per scene.
constexpr size_t kMaxRegionsPerQuad = 256;
constexpr size_t kMaxProducts = 64;
// A product, once scaled, measures at most 10 m along each axis (furniture, not a building;
// the kiosk's product files have the same bound).
constexpr double kMaxProductSize = 10;

// Display response parameters: value = 255 * min(1, exposure * L)^(1 / gamma)
// (shadow::ToneCurve::gamma).
struct ToneParameters {
  double exposure = 1;
  double gamma = 2.2;
};

struct Product {
  std::string name;
  std::filesystem::path model;  // resolved against the scene file's folder
  double scale = 1;
  double rotateYDegrees = 0;
  bool restOnFloor = true;
  // Diffuse colour of the virtual object: the scene file's `colour`; without it, the mean of
  // mesh.reflectances (OBJ materials, glTF base colour). Per-vertex colours
  // (mesh.reflectances) are what is shaded when the model has them and `colour` is not
  // given: `colour` overrides the model's colours (it is the one knob a scene file has).
  glm::dvec3 reflectance{0.5};
  // Phong-like specular lobe (Gibson & Chalmers 2003 §5): reflectance in [0, 1] per
  // channel (0 = none) and exponent; from a glTF model's metallic/roughness (gltf_io.h).
  glm::dvec3 specular{0.0};
  double specularExponent = 0;
  size_t proxyTriangles = 300;
  // `fine_proxy_triangles`: a second, finer shadow proxy that the frame's most energetic
  // passes draw (shadow/pass_list.h); 0 (the default) gives none. More than proxyTriangles.
  size_t fineProxyTriangles = 0;
  // `fine_proxy_passes`: how many of a frame's passes draw the fine proxy (stated at 50
  // passes, shadow/pass_list.h fineProxyPassesFor; 50 or more: every pass); unset: the
  // bundle's default. Needs fine_proxy_triangles. Precompute writes it into the bundle's
  // render settings (shadow/render_settings.h productFineProxyPasses).
  std::optional<uint32_t> fineProxyPasses;
  // `solid`: the product is a solid object, so its proxies' holes are capped
  // (scene/hole_capping.h) and they can be drawn front faces only. False by default: a
  // lampshade's openings let light through.
  bool solid = false;
  // Normals a model does not give are split at this angle (mesh_io.h), `crease_angle_deg`.
  double creaseAngleDegrees = kDefaultCreaseAngleDegrees;
  // The model in product space: scaled, rotated about +y, its bounding box centred on
  // x = z = 0 and, with restOnFloor, its lowest point at y = 0 (so a pose (x, z, yaw)
  // places it standing on the floor).
  TriangleMesh mesh;
  TriangleMesh proxy;      // simplifyForShadows(mesh, proxyTriangles), same space (positions only)
  TriangleMesh fineProxy;  // simplifyForShadows(mesh, fineProxyTriangles), or empty
  // The loader's warnings and the size check's (product_size.h), each naming the model file.
  std::vector<std::string> warnings;
};

// Where the product is first shown: its product-space origin moved to (x, 0, z) after
// a rotation of yawDegrees about +y.
struct StartPose {
  uint32_t product = 0;
  double x = 0, z = 0, yawDegrees = 0;
};

struct SceneDescription {
  std::filesystem::path source;  // the scene file
  uint32_t width = 0, height = 0;
  Camera camera;  // aspect = width / height
  RoomDescription room;
  double patchSize = 0;  // metres
  // Patches at most this size around solid boxes' bases (RoomDescription::refineAroundSolids,
  // scene key "contact_patch_size"); 0: none.
  double contactPatchSize = 0;
  // Gibson 2003 §4: share of the emitted power the source set holds (optional field
  // `power_share`); the rest of the light is never shadowed.
  double powerShare = 0.7;
  ToneParameters tone;
  std::vector<Product> products;
  StartPose startPose;
};

// Reads and validates a scene file; model paths are relative to its folder.
SceneDescription loadSceneFile(const std::filesystem::path& path);

// The same from JSON text; `path` names the file in messages and anchors relative model
// paths (it need not exist).
SceneDescription parseSceneFile(std::string_view text, const std::filesystem::path& path);

// Issue 17's proxy scene models: every product's shadow proxy and fine proxy simplified again
// to `scale` times the scene file's triangle counts (rounded; at least 4, a fine proxy still
// larger than its proxy, at most 100,000). A proxy's triangles are what each pass draws into
// its shadow map: fewer are cheaper and further from the product's silhouette. Throws
// std::invalid_argument unless scale is in (0, 16].
void scaleShadowProxies(SceneDescription& scene, double scale);

}  // namespace penumbra::scene
