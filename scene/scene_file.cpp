#include "scene/scene_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "core/json_reader.h"
#include "scene/gltf_io.h"
#include "scene/hole_capping.h"
#include "scene/mesh_simplify.h"
#include "scene/product_size.h"

namespace penumbra::scene {

namespace {

using core::JsonValue;

// Scene-specific value rules on top of core::JsonValue's typed reads.
double positive(const JsonValue& v) {
  const double d = v.number();
  if (!(d > 0)) v.fail("must be positive");
  return d;
}
uint32_t count(const JsonValue& v, int64_t lo, int64_t hi) {
  return static_cast<uint32_t>(v.integer(lo, hi));
}
glm::dvec3 vec3(const JsonValue& v) {
  const std::vector<double> c = v.numbers(3);
  return glm::dvec3(c[0], c[1], c[2]);
}
// Diffuse reflectance: each channel in [0, 1] (energy conservation).
glm::dvec3 colour(const JsonValue& v) {
  v.numbers(3);  // three numbers, or the message names the one that is not
  const std::vector<JsonValue> c = v.array();
  return glm::dvec3(c[0].number(0, 1), c[1].number(0, 1), c[2].number(0, 1));
}
// A point of the room: finite, and within kMaxRoomCoordinate of the origin on every axis
// (checked before any arithmetic: a corner of 3e20 m aborted Embree inside precompute).
glm::dvec3 roomPoint(const JsonValue& v) {
  const glm::dvec3 p = vec3(v);
  for (int k = 0; k < 3; ++k) {
    if (!(std::abs(p[k]) <= kMaxRoomCoordinate)) {
      v.fail(core::formatNumber(p[k]) + " m is not a room (every coordinate of the room lies " +
             "within ±" + core::formatNumber(kMaxRoomCoordinate) + " m of the origin)");
    }
  }
  return p;
}
// A quad edge: any vector that keeps the quad inside the room's coordinate range.
glm::dvec3 roomEdge(const JsonValue& v, const glm::dvec3& origin) {
  const glm::dvec3 e = vec3(v);
  for (int k = 0; k < 3; ++k) {
    if (!(std::abs(origin[k] + e[k]) <= kMaxRoomCoordinate)) {
      v.fail("reaches " + core::formatNumber(origin[k] + e[k]) +
             " m, which is not a room (every coordinate of the room lies within ±" +
             core::formatNumber(kMaxRoomCoordinate) + " m of the origin)");
    }
  }
  if (!(glm::length(e) >= kMinRoomExtent)) {
    v.fail("is " + core::formatNumber(glm::length(e)) + " m long, less than the " +
           core::formatNumber(kMinRoomExtent) + " m a quad edge must measure");
  }
  return e;
}
// A patch size in metres within [kMinPatchSize, kMaxPatchSize].
double patchSize(const JsonValue& v) {
  return v.number(kMinPatchSize, kMaxPatchSize);
}
// The distance from `p` to the box (0 inside).
double distanceToBox(const glm::dvec3& p, const Aabb& b) {
  return glm::length(glm::max(glm::max(b.min - p, p - b.max), glm::dvec3(0.0)));
}
Aabb roomBounds(const RoomDescription& room) {
  Aabb b = Aabb::emptyBox();
  for (const Quad& q : room.quads) {
    for (const glm::dvec3& c :
         {q.origin, q.origin + q.edgeU, q.origin + q.edgeV, q.origin + q.edgeU + q.edgeV}) {
      b.extend(c);
    }
  }
  return b;
}

// Two increasing numbers [a, b].
std::pair<double, double> range(const JsonValue& v) {
  const std::vector<double> ab = v.numbers(2);
  if (!(ab[0] < ab[1])) v.fail("must be increasing");
  return {ab[0], ab[1]};
}

// ---------------------------------------------------------------------------------------

class SceneParser {
 public:
  explicit SceneParser(const std::filesystem::path& path) : path_(path) {}

  SceneDescription parse(const JsonValue& doc) {
    doc.object({"format", "version", "image", "camera", "materials", "room", "patch_size",
                "contact_patch_size", "shadow_boundary_patch_size", "power_share", "tone",
                "products", "start_pose"});
    const JsonValue format = doc["format"];
    if (!format.json().is_string() || format.string() != "penumbra-scene") {
      format.fail("must be \"penumbra-scene\"");
    }
    const JsonValue version = doc["version"];
    if (!version.json().is_number_integer() || version.json().get<int64_t>() != 1) {
      version.fail("unsupported (this program reads version 1)");
    }

    SceneDescription s;
    s.source = path_;
    const JsonValue image = doc["image"].object({"width", "height"});
    // 16384 bounds the frame buffers the kiosk would allocate.
    s.width = count(image["width"], 1, 16384);
    s.height = count(image["height"], 1, 16384);

    s.camera = parseCamera(doc["camera"], static_cast<double>(s.width) / s.height);
    if (const auto m = doc.find("materials")) parseMaterials(*m);
    s.room = parseRoom(doc["room"]);
    s.patchSize = patchSize(doc["patch_size"]);
    if (const auto contact = doc.find("contact_patch_size")) {
      s.contactPatchSize = patchSize(*contact);
      s.room.refineAroundSolids(s.contactPatchSize);
    }
    if (const auto boundary = doc.find("shadow_boundary_patch_size")) {
      s.room.shadowBoundaryPatchSize = patchSize(*boundary);
    }
    const double patches = patchCount(s.room, s.patchSize);
    if (patches > kMaxPatches) {
      doc["patch_size"].fail(core::formatNumber(s.patchSize) + " m cuts the room into " +
                             core::formatNumber(patches) + " patches, more than the " +
                             core::formatNumber(kMaxPatches) +
                             " precompute handles: use a larger patch_size" +
                             (s.contactPatchSize > 0 ? " or contact_patch_size" : ""));
    }
    const Aabb bounds = roomBounds(s.room);
    const double eyeDistance = distanceToBox(s.camera.eye, bounds);
    if (eyeDistance > kMaxCameraDistanceFromRoom) {
      doc["camera"]["eye"].fail("is " + core::formatNumber(std::round(eyeDistance)) +
                                " m from the room, expected " + "within " +
                                core::formatNumber(kMaxCameraDistanceFromRoom) + " m of it");
    }
    if (const auto share = doc.find("power_share")) {
      s.powerShare = positive(*share);
      if (s.powerShare > 1.0) share->fail("must be in (0, 1]");
    }

    const JsonValue tone = doc["tone"].object({"exposure", "gamma"});
    s.tone.exposure = positive(tone["exposure"]);
    s.tone.gamma = positive(tone["gamma"]);

    const std::vector<JsonValue> products = doc["products"].array(1);
    if (products.size() > kMaxProducts) {
      doc["products"].fail(std::to_string(products.size()) + " products, more than the " +
                           std::to_string(kMaxProducts) + " a scene may have");
    }
    for (const JsonValue& product : products) s.products.push_back(parseProduct(product));

    const JsonValue pose = doc["start_pose"].object({"product", "x", "z", "yaw_deg"});
    s.startPose.product = count(pose["product"], 0, static_cast<int64_t>(s.products.size()) - 1);
    // On the floor of the room (its bounding box's footprint).
    s.startPose.x = pose["x"].number(bounds.min.x, bounds.max.x);
    s.startPose.z = pose["z"].number(bounds.min.z, bounds.max.z);
    s.startPose.yawDegrees = 0;
    if (const auto yaw = pose.find("yaw_deg")) s.startPose.yawDegrees = yaw->number();
    return s;
  }

 private:
  Camera parseCamera(const JsonValue& v, double aspect) {
    v.object({"eye", "target", "up", "fov_y_deg", "near", "far"});
    Camera c;
    c.eye = vec3(v["eye"]);
    c.target = vec3(v["target"]);
    c.up = glm::dvec3(0, 1, 0);
    if (const auto up = v.find("up")) c.up = vec3(*up);
    c.fovYDegrees = v["fov_y_deg"].number();
    if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180)) v["fov_y_deg"].fail("must be in (0, 180)");
    c.zNear = v["near"].number(kMinCameraNear, kMaxCameraFar);
    c.zFar = v["far"].number(kMinCameraNear, kMaxCameraFar);
    if (!(c.zFar > c.zNear)) v["far"].fail("must be greater than camera.near");
    c.aspect = aspect;
    try {
      (void)c.view();  // eye == target, or up along the view direction
    } catch (const std::invalid_argument& e) {
      v.fail(e.what());
    }
    return c;
  }

  void parseMaterials(const JsonValue& v) {
    for (const auto& [name, m] : v.members()) {
      if (!name.empty() && name[0] == '_') continue;
      materials_[name] = parseMaterialObject(m);
    }
  }

  // {"reflectance": [r, g, b], "emission": [r, g, b]}: at least one of them; the other
  // is zero (an emitter reflects nothing of note, a reflector emits nothing).
  Material parseMaterialObject(const JsonValue& v) {
    v.object({"reflectance", "emission"});
    const auto refl = v.find("reflectance");
    const auto emis = v.find("emission");
    if (!refl && !emis) v.fail("needs reflectance or emission");
    Material m{glm::dvec3(0.0), glm::dvec3(0.0)};
    if (refl) m.reflectance = colour(*refl);
    if (emis) {
      m.emission = vec3(*emis);
      for (int k = 0; k < 3; ++k) {
        const JsonValue channel = emis->array()[static_cast<size_t>(k)];
        if (m.emission[k] < 0) channel.fail("must not be negative");
        if (m.emission[k] > kMaxEmission) {
          channel.fail(core::formatNumber(m.emission[k]) + " is not a lamp (at most " +
                       core::formatNumber(kMaxEmission) + ")");
        }
      }
    }
    return m;
  }

  // A material is either inline or the name of an entry of "materials".
  Material material(const JsonValue& v) {
    if (v.json().is_string()) {
      const auto it = materials_.find(v.string());
      if (it == materials_.end()) {
        v.fail("no material named \"" + v.string() + "\" in materials");
      }
      return it->second;
    }
    return parseMaterialObject(v);
  }

  static Aabb box(const JsonValue& obj) {
    const Aabb b{roomPoint(obj["min"]), roomPoint(obj["max"])};
    if (!(b.min.x < b.max.x && b.min.y < b.max.y && b.min.z < b.max.z)) {
      obj["max"].fail("must exceed min on every axis");
    }
    const glm::dvec3 size = b.max - b.min;
    for (int k = 0; k < 3; ++k) {
      if (!(size[k] >= kMinRoomExtent)) {
        obj["max"].fail("exceeds min by " + core::formatNumber(size[k]) + " m on axis " + "xyz"[k] +
                        ", less than the " + core::formatNumber(kMinRoomExtent) +
                        " m a box must measure");
      }
    }
    return b;
  }

  RoomDescription parseRoom(const JsonValue& v) {
    v.object({"shell", "quads", "boxes", "regions"});
    RoomDescription room;
    if (const auto shell = v.find("shell")) {
      shell->object({"min", "max", "floor", "walls", "ceiling"});
      const Aabb b = box(*shell);
      room.addRoomShell(b, material((*shell)["floor"]), material((*shell)["walls"]),
                        material((*shell)["ceiling"]));
    }
    if (const auto quads = v.find("quads")) {
      for (const JsonValue& q : quads->array()) {
        q.object({"name", "origin", "edge_u", "edge_v", "material"});
        Quad quad;
        quad.name = q["name"].nonEmptyString();
        quad.origin = roomPoint(q["origin"]);
        quad.edgeU = roomEdge(q["edge_u"], quad.origin);
        quad.edgeV = roomEdge(q["edge_v"], quad.origin);
        quad.material = material(q["material"]);
        try {
          room.addQuad(std::move(quad));
        } catch (const std::invalid_argument& e) {
          q.fail(e.what());
        }
      }
    }
    if (const auto boxes = v.find("boxes")) {
      for (const JsonValue& b : boxes->array()) {
        b.object({"name", "min", "max", "material", "with_bottom"});
        const std::string name = b["name"].nonEmptyString();
        const Aabb extent = box(b);
        const Material m = material(b["material"]);
        // A box standing on the floor hides its bottom; default to that common case.
        const bool withBottom = b.booleanOr("with_bottom", false);
        room.addSolidBox(name, extent, m, withBottom);
      }
    }
    if (room.quads.empty()) v.fail("has no shell, quads or boxes");
    // Quad names must be unique so regions can address them.
    std::map<std::string, uint32_t> byName;
    for (uint32_t i = 0; i < room.quads.size(); ++i) {
      if (!byName.emplace(room.quads[i].name, i).second) {
        v.fail("two quads are named \"" + room.quads[i].name + "\"");
      }
    }
    if (const auto regions = v.find("regions")) {
      for (const JsonValue& region : regions->array()) parseRegion(region, byName, room);
    }
    return room;
  }

  // {"quad", "name", "u": [from, to], "v": [from, to], "material", "patch_size"}: u and v
  // in metres from the quad's origin along edge_u and edge_v (shell quads: see README).
  void parseRegion(const JsonValue& v, const std::map<std::string, uint32_t>& byName,
                   RoomDescription& room) {
    v.object({"quad", "name", "u", "v", "material", "patch_size"});
    const std::string quadName = v["quad"].nonEmptyString();
    const auto it = byName.find(quadName);
    if (it == byName.end()) v["quad"].fail("no quad named \"" + quadName + "\"");
    Quad& q = room.quads[it->second];
    Region region;
    region.name = v["name"].nonEmptyString();
    const double lu = glm::length(q.edgeU), lv = glm::length(q.edgeV);
    const auto [u0, u1] = range(v["u"]);
    const auto [v0, v1] = range(v["v"]);
    if (u0 < 0 || u1 > lu) v["u"].fail("must lie within [0, " + std::to_string(lu) + "] m");
    if (v0 < 0 || v1 > lv) v["v"].fail("must lie within [0, " + std::to_string(lv) + "] m");
    region.s0 = u0 / lu;
    region.s1 = u1 / lu;
    region.t0 = v0 / lv;
    region.t1 = v1 / lv;
    region.material = material(v["material"]);
    if (const auto ps = v.find("patch_size")) region.patchSize = patchSize(*ps);
    if (q.regions.size() >= kMaxRegionsPerQuad) {
      v.fail("quad \"" + quadName + "\" has more than " + std::to_string(kMaxRegionsPerQuad) +
             " regions");
    }
    // The patch mesh gives each cell one material; overlapping regions would make that
    // depend on their order.
    for (const Region& other : q.regions) {
      if (region.s0 < other.s1 && other.s0 < region.s1 && region.t0 < other.t1 &&
          other.t0 < region.t1) {
        v.fail("overlaps region \"" + other.name + "\" of quad \"" + quadName + "\"");
      }
    }
    q.regions.push_back(std::move(region));
  }

  Product parseProduct(const JsonValue& v) {
    v.object({"name", "model", "scale", "rotate_y_deg", "rest_on_floor", "colour",
              "proxy_triangles", "fine_proxy_triangles", "fine_proxy_passes", "solid", "specular",
              "specular_exponent", "crease_angle_deg"});
    Product p;
    p.name = v["name"].nonEmptyString();
    const std::string model = v["model"].nonEmptyString();
    p.model = path_.parent_path() / model;
    if (const auto s = v.find("scale")) p.scale = positive(*s);
    if (const auto rot = v.find("rotate_y_deg")) p.rotateYDegrees = rot->number();
    if (const auto rest = v.find("rest_on_floor")) p.restOnFloor = rest->boolean();
    if (const auto n = v.find("proxy_triangles")) p.proxyTriangles = count(*n, 4, 100000);
    if (const auto n = v.find("fine_proxy_triangles")) {
      p.fineProxyTriangles = count(*n, 4, 100000);
      if (p.fineProxyTriangles <= p.proxyTriangles) {
        n->fail("must be more than proxy_triangles (" + std::to_string(p.proxyTriangles) + ")");
      }
    }
    if (const auto n = v.find("fine_proxy_passes")) {
      if (p.fineProxyTriangles == 0) n->fail("needs fine_proxy_triangles (a fine proxy to draw)");
      // The renderer's pass limit (shadow/render_settings.h kMaxSettingsPasses).
      p.fineProxyPasses = count(*n, 0, 257);
    }
    if (const auto s = v.find("solid")) p.solid = s->boolean();
    if (const auto a = v.find("crease_angle_deg")) p.creaseAngleDegrees = a->number(0, 180);
    std::string ext = p.model.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const bool gltf = ext == ".gltf" || ext == ".glb";
    MeshOptions options;
    options.creaseAngleDegrees = p.creaseAngleDegrees;
    try {
#ifdef PENUMBRA_HAVE_GLTF
      if (gltf) {
        // glTF carries its own material (gltf_io.h): "colour", "specular" and
        // "specular_exponent" below override it when given.
        const GltfModel loaded = loadGltf(p.model);
        p.mesh = loaded.mesh;
        p.reflectance = loaded.material.diffuse;
        p.specular = loaded.material.specular;
        p.specularExponent = loaded.material.specularExponent;
      } else {
        p.mesh = loadMesh(p.model, options);
      }
#else
      p.mesh = loadMesh(p.model, options);
#endif
    } catch (const MeshError& e) {
      v["model"].fail(e.what());
    }
    p.warnings = p.mesh.warnings;
    if (const auto c = v.find("colour")) {
      p.reflectance = colour(*c);
      p.mesh.reflectances.clear();  // the scene's colour overrides the model's
    } else if (!p.mesh.reflectances.empty()) {
      if (!gltf) p.reflectance = meanReflectance(p.mesh);
    } else {
      v["colour"];  // a model without colours (PLY, OBJ without materials): "missing"
    }
    if (const auto c = v.find("specular")) p.specular = colour(*c);
    if (const auto e = v.find("specular_exponent")) p.specularExponent = e->number(0, 1e6);
    placeInProductSpace(p);
    const glm::dvec3 size = p.mesh.bounds().size();
    const double largest = std::max({size.x, size.y, size.z});
    if (!(largest <= kMaxProductSize)) {
      v["model"].fail("is " + core::formatNumber(largest) + " m across once scaled, more than " +
                      "the " + core::formatNumber(kMaxProductSize) +
                      " m a product may measure (check scale)");
    }
    if (const auto w = productSizeWarning(p.model.string(), largest, p.scale, gltf)) {
      p.warnings.push_back(*w);
    }
    if (p.solid) {
      TriangleMesh capped = weldVertices(p.mesh);
      if (!capHoles(capped)) {
        p.warnings.push_back(p.model.string() +
                             ": solid: the model's holes are not simple loops; its shadow "
                             "proxies are left open (drawn with both faces)");
      }
    }
    p.proxy = simplifyForShadows(p.mesh, p.proxyTriangles, p.solid);
    if (p.fineProxyTriangles > 0) {
      p.fineProxy = simplifyForShadows(p.mesh, p.fineProxyTriangles, p.solid);
    }
    return p;
  }

  // The vertices' mean reflectance, summed in vertex order: the product's one colour where a
  // single one is needed (a bundle reader that ignores per-vertex colours).
  static glm::dvec3 meanReflectance(const TriangleMesh& mesh) {
    glm::dvec3 sum(0.0);
    for (const glm::dvec3& r : mesh.reflectances) sum += r;
    return glm::clamp(sum / double(mesh.reflectances.size()), 0.0, 1.0);
  }

  // Scale, rotate about +y, then centre the footprint on the origin and (restOnFloor)
  // put the lowest point on y = 0.
  static void placeInProductSpace(Product& p) {
    const double a = p.rotateYDegrees * std::numbers::pi / 180.0;
    const double c = std::cos(a), s = std::sin(a);
    for (glm::dvec3& q : p.mesh.positions) {
      const glm::dvec3 scaled = q * p.scale;
      q = glm::dvec3(c * scaled.x + s * scaled.z, scaled.y, -s * scaled.x + c * scaled.z);
    }
    // Normals turn with the model (a uniform positive scale leaves them be), renormalized.
    for (glm::dvec3& n : p.mesh.normals) {
      n = glm::normalize(glm::dvec3(c * n.x + s * n.z, n.y, -s * n.x + c * n.z));
    }
    const Aabb b = p.mesh.bounds();
    const glm::dvec3 shift(-b.centre().x, p.restOnFloor ? -b.min.y : 0.0, -b.centre().z);
    for (glm::dvec3& q : p.mesh.positions) q += shift;
  }

  std::filesystem::path path_;
  std::map<std::string, Material> materials_;
};

}  // namespace

SceneDescription parseSceneFile(std::string_view text, const std::filesystem::path& path) {
  const core::JsonDocument doc(text, path.string(), core::throwAs<SceneFileError>);
  return SceneParser(path).parse(doc.root());
}

SceneDescription loadSceneFile(const std::filesystem::path& path) {
  const core::JsonDocument doc(path, core::throwAs<SceneFileError>);
  return SceneParser(path).parse(doc.root());
}

void scaleShadowProxies(SceneDescription& scene, double scale) {
  if (!(scale > 0 && scale <= 16)) {
    throw std::invalid_argument("proxy scale " + core::formatNumber(scale) + " is not in (0, 16]");
  }
  static constexpr size_t kMinTriangles = 4, kMaxTriangles = 100'000;  // the scene file's bounds
  const auto scaled = [scale](size_t n, size_t least) {
    return std::clamp<size_t>(static_cast<size_t>(std::llround(double(n) * scale)), least,
                              kMaxTriangles);
  };
  for (Product& p : scene.products) {
    p.proxyTriangles = scaled(p.proxyTriangles, kMinTriangles);
    p.proxy = simplifyForShadows(p.mesh, p.proxyTriangles, p.solid);
    if (p.fineProxyTriangles == 0) continue;
    p.fineProxyTriangles = scaled(p.fineProxyTriangles, p.proxyTriangles + 1);
    p.fineProxy = simplifyForShadows(p.mesh, p.fineProxyTriangles, p.solid);
  }
}

}  // namespace penumbra::scene
