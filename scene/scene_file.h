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
  glm::dvec3 reflectance{0.5};  // diffuse colour of the virtual object
  // Phong-like specular lobe (Gibson & Chalmers 2003 §5): reflectance in [0, 1] per
  // channel (0 = none) and exponent; from a glTF model's metallic/roughness (gltf_io.h).
  glm::dvec3 specular{0.0};
  double specularExponent = 0;
  size_t proxyTriangles = 300;
  // The model in product space: scaled, rotated about +y, its bounding box centred on
  // x = z = 0 and, with restOnFloor, its lowest point at y = 0 (so a pose (x, z, yaw)
  // places it standing on the floor).
  TriangleMesh mesh;
  TriangleMesh proxy;  // simplifyForShadows(mesh, proxyTriangles), same space
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

}  // namespace penumbra::scene
