#include "scene/scene_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include <nlohmann/json.hpp>

#include "scene/gltf_io.h"
#include "scene/mesh_simplify.h"

namespace penumbra::scene {

namespace {

using nlohmann::json;

// Field paths are written as in the file: "room.boxes[0].min".
std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string at(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw SceneFileError(file_ + ": " + (field.empty() ? "" : field + ": ") + what);
  }

  // `v` must be an object whose keys are all in `allowed`; keys starting with '_' are
  // free-form notes (JSON has no comments).
  void object(const json& v, const std::string& path,
              std::initializer_list<std::string_view> allowed) const {
    if (!v.is_object()) fail(path, "must be an object");
    for (const auto& [key, value] : v.items()) {
      if (!key.empty() && key[0] == '_') continue;
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        fail(join(path, key), "unknown field");
      }
    }
  }

  const json& required(const json& obj, const std::string& path, const char* key) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(join(path, key), "missing");
    return *it;
  }
  const json* optional(const json& obj, const char* key) const {
    const auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }

  double number(const json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, "must be a number, got " + std::string(v.type_name()));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "must be finite");
    return d;
  }
  double positive(const json& v, const std::string& path) const {
    const double d = number(v, path);
    if (!(d > 0)) fail(path, "must be positive");
    return d;
  }
  uint32_t count(const json& v, const std::string& path, uint64_t lo, uint64_t hi) const {
    if (!v.is_number_integer()) fail(path, "must be an integer");
    // nlohmann stores non-negative integers as unsigned and negative ones as signed.
    const bool negative = !v.is_number_unsigned() && v.get<int64_t>() < 0;
    const uint64_t u = negative ? 0 : v.get<uint64_t>();
    if (negative || u < lo || u > hi) {
      fail(path, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return static_cast<uint32_t>(u);
  }
  bool boolean(const json& v, const std::string& path) const {
    if (!v.is_boolean()) fail(path, "must be true or false");
    return v.get<bool>();
  }
  std::string string(const json& v, const std::string& path) const {
    if (!v.is_string() || v.get<std::string>().empty()) fail(path, "must be a non-empty string");
    return v.get<std::string>();
  }
  glm::dvec3 vec3(const json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != 3) fail(path, "must be an array of 3 numbers");
    return glm::dvec3(number(v[0], at(path, 0)), number(v[1], at(path, 1)),
                      number(v[2], at(path, 2)));
  }
  // Diffuse reflectance: each channel in [0, 1] (energy conservation).
  glm::dvec3 colour(const json& v, const std::string& path) const {
    const glm::dvec3 c = vec3(v, path);
    for (int k = 0; k < 3; ++k) {
      if (c[k] < 0 || c[k] > 1) fail(at(path, static_cast<size_t>(k)), "must be in [0, 1]");
    }
    return c;
  }
  // Two increasing numbers [a, b].
  std::pair<double, double> range(const json& v, const std::string& path) const {
    if (!v.is_array() || v.size() != 2) fail(path, "must be an array [from, to]");
    const double a = number(v[0], at(path, 0)), b = number(v[1], at(path, 1));
    if (!(a < b)) fail(path, "must be increasing");
    return {a, b};
  }

 private:
  std::string file_;
};

// ---------------------------------------------------------------------------------------

class SceneParser {
 public:
  SceneParser(const Reader& r, const std::filesystem::path& path) : r_(r), path_(path) {}

  SceneDescription parse(const json& doc) {
    r_.object(doc, "",
              {"format", "version", "image", "camera", "materials", "room", "patch_size",
               "power_share", "tone", "products", "start_pose"});
    const json& format = r_.required(doc, "", "format");
    if (!format.is_string() || format.get<std::string>() != "penumbra-scene") {
      r_.fail("format", "must be \"penumbra-scene\"");
    }
    const json& version = r_.required(doc, "", "version");
    if (!version.is_number_integer() || version.get<int64_t>() != 1) {
      r_.fail("version", "unsupported (this program reads version 1)");
    }

    SceneDescription s;
    s.source = path_;
    const json& image = r_.required(doc, "", "image");
    r_.object(image, "image", {"width", "height"});
    // 16384 bounds the frame buffers the kiosk would allocate.
    s.width = r_.count(r_.required(image, "image", "width"), "image.width", 1, 16384);
    s.height = r_.count(r_.required(image, "image", "height"), "image.height", 1, 16384);

    s.camera = parseCamera(r_.required(doc, "", "camera"), static_cast<double>(s.width) / s.height);
    if (const json* m = r_.optional(doc, "materials")) parseMaterials(*m);
    s.room = parseRoom(r_.required(doc, "", "room"));
    s.patchSize = r_.positive(r_.required(doc, "", "patch_size"), "patch_size");
    if (const json* share = r_.optional(doc, "power_share")) {
      s.powerShare = r_.positive(*share, "power_share");
      if (s.powerShare > 1.0) r_.fail("power_share", "must be in (0, 1]");
    }

    const json& tone = r_.required(doc, "", "tone");
    r_.object(tone, "tone", {"exposure", "gamma"});
    s.tone.exposure = r_.positive(r_.required(tone, "tone", "exposure"), "tone.exposure");
    s.tone.gamma = r_.positive(r_.required(tone, "tone", "gamma"), "tone.gamma");

    const json& products = r_.required(doc, "", "products");
    if (!products.is_array() || products.empty()) {
      r_.fail("products", "must be a non-empty array");
    }
    for (size_t i = 0; i < products.size(); ++i) {
      s.products.push_back(parseProduct(products[i], at("products", i)));
    }

    const json& pose = r_.required(doc, "", "start_pose");
    r_.object(pose, "start_pose", {"product", "x", "z", "yaw_deg"});
    s.startPose.product = r_.count(r_.required(pose, "start_pose", "product"), "start_pose.product",
                                   0, s.products.size() - 1);
    s.startPose.x = r_.number(r_.required(pose, "start_pose", "x"), "start_pose.x");
    s.startPose.z = r_.number(r_.required(pose, "start_pose", "z"), "start_pose.z");
    s.startPose.yawDegrees = 0;
    if (const json* yaw = r_.optional(pose, "yaw_deg")) {
      s.startPose.yawDegrees = r_.number(*yaw, "start_pose.yaw_deg");
    }
    return s;
  }

 private:
  Camera parseCamera(const json& v, double aspect) {
    r_.object(v, "camera", {"eye", "target", "up", "fov_y_deg", "near", "far"});
    Camera c;
    c.eye = r_.vec3(r_.required(v, "camera", "eye"), "camera.eye");
    c.target = r_.vec3(r_.required(v, "camera", "target"), "camera.target");
    c.up = glm::dvec3(0, 1, 0);
    if (const json* up = r_.optional(v, "up")) c.up = r_.vec3(*up, "camera.up");
    c.fovYDegrees = r_.number(r_.required(v, "camera", "fov_y_deg"), "camera.fov_y_deg");
    if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180)) {
      r_.fail("camera.fov_y_deg", "must be in (0, 180)");
    }
    c.zNear = r_.positive(r_.required(v, "camera", "near"), "camera.near");
    c.zFar = r_.number(r_.required(v, "camera", "far"), "camera.far");
    if (!(c.zFar > c.zNear)) r_.fail("camera.far", "must be greater than camera.near");
    c.aspect = aspect;
    try {
      (void)c.view();  // eye == target, or up along the view direction
    } catch (const std::invalid_argument& e) {
      r_.fail("camera", e.what());
    }
    return c;
  }

  void parseMaterials(const json& v) {
    if (!v.is_object()) r_.fail("materials", "must be an object of named materials");
    for (const auto& [name, m] : v.items()) {
      if (!name.empty() && name[0] == '_') continue;
      materials_[name] = parseMaterialObject(m, join("materials", name));
    }
  }

  // {"reflectance": [r, g, b], "emission": [r, g, b]}: at least one of them; the other
  // is zero (an emitter reflects nothing of note, a reflector emits nothing).
  Material parseMaterialObject(const json& v, const std::string& path) {
    r_.object(v, path, {"reflectance", "emission"});
    const json* refl = r_.optional(v, "reflectance");
    const json* emis = r_.optional(v, "emission");
    if (!refl && !emis) r_.fail(path, "needs reflectance or emission");
    Material m{glm::dvec3(0.0), glm::dvec3(0.0)};
    if (refl) m.reflectance = r_.colour(*refl, join(path, "reflectance"));
    if (emis) {
      m.emission = r_.vec3(*emis, join(path, "emission"));
      for (int k = 0; k < 3; ++k) {
        if (m.emission[k] < 0) {
          r_.fail(at(join(path, "emission"), static_cast<size_t>(k)), "must not be negative");
        }
      }
    }
    return m;
  }

  // A material is either inline or the name of an entry of "materials".
  Material material(const json& v, const std::string& path) {
    if (v.is_string()) {
      const auto it = materials_.find(v.get<std::string>());
      if (it == materials_.end()) {
        r_.fail(path, "no material named \"" + v.get<std::string>() + "\" in materials");
      }
      return it->second;
    }
    return parseMaterialObject(v, path);
  }

  Aabb box(const json& obj, const std::string& path) {
    const Aabb b{r_.vec3(r_.required(obj, path, "min"), join(path, "min")),
                 r_.vec3(r_.required(obj, path, "max"), join(path, "max"))};
    if (!(b.min.x < b.max.x && b.min.y < b.max.y && b.min.z < b.max.z)) {
      r_.fail(join(path, "max"), "must exceed min on every axis");
    }
    return b;
  }

  RoomDescription parseRoom(const json& v) {
    r_.object(v, "room", {"shell", "quads", "boxes", "regions"});
    RoomDescription room;
    if (const json* shell = r_.optional(v, "shell")) {
      r_.object(*shell, "room.shell", {"min", "max", "floor", "walls", "ceiling"});
      const Aabb b = box(*shell, "room.shell");
      room.addRoomShell(
          b, material(r_.required(*shell, "room.shell", "floor"), "room.shell.floor"),
          material(r_.required(*shell, "room.shell", "walls"), "room.shell.walls"),
          material(r_.required(*shell, "room.shell", "ceiling"), "room.shell.ceiling"));
    }
    if (const json* quads = r_.optional(v, "quads")) {
      if (!quads->is_array()) r_.fail("room.quads", "must be an array");
      for (size_t i = 0; i < quads->size(); ++i) {
        const json& q = (*quads)[i];
        const std::string path = at("room.quads", i);
        r_.object(q, path, {"name", "origin", "edge_u", "edge_v", "material"});
        Quad quad;
        quad.name = r_.string(r_.required(q, path, "name"), join(path, "name"));
        quad.origin = r_.vec3(r_.required(q, path, "origin"), join(path, "origin"));
        quad.edgeU = r_.vec3(r_.required(q, path, "edge_u"), join(path, "edge_u"));
        quad.edgeV = r_.vec3(r_.required(q, path, "edge_v"), join(path, "edge_v"));
        quad.material = material(r_.required(q, path, "material"), join(path, "material"));
        try {
          room.addQuad(std::move(quad));
        } catch (const std::invalid_argument& e) {
          r_.fail(path, e.what());
        }
      }
    }
    if (const json* boxes = r_.optional(v, "boxes")) {
      if (!boxes->is_array()) r_.fail("room.boxes", "must be an array");
      for (size_t i = 0; i < boxes->size(); ++i) {
        const json& b = (*boxes)[i];
        const std::string path = at("room.boxes", i);
        r_.object(b, path, {"name", "min", "max", "material", "with_bottom"});
        const std::string name = r_.string(r_.required(b, path, "name"), join(path, "name"));
        const Aabb extent = box(b, path);
        const Material m = material(r_.required(b, path, "material"), join(path, "material"));
        // A box standing on the floor hides its bottom; default to that common case.
        bool withBottom = false;
        if (const json* wb = r_.optional(b, "with_bottom")) {
          withBottom = r_.boolean(*wb, join(path, "with_bottom"));
        }
        room.addSolidBox(name, extent, m, withBottom);
      }
    }
    if (room.quads.empty()) r_.fail("room", "has no shell, quads or boxes");
    // Quad names must be unique so regions can address them.
    std::map<std::string, uint32_t> byName;
    for (uint32_t i = 0; i < room.quads.size(); ++i) {
      if (!byName.emplace(room.quads[i].name, i).second) {
        r_.fail("room", "two quads are named \"" + room.quads[i].name + "\"");
      }
    }
    if (const json* regions = r_.optional(v, "regions")) {
      if (!regions->is_array()) r_.fail("room.regions", "must be an array");
      for (size_t i = 0; i < regions->size(); ++i) {
        parseRegion((*regions)[i], at("room.regions", i), byName, room);
      }
    }
    return room;
  }

  // {"quad", "name", "u": [from, to], "v": [from, to], "material", "patch_size"}: u and v
  // in metres from the quad's origin along edge_u and edge_v (shell quads: see README).
  void parseRegion(const json& v, const std::string& path,
                   const std::map<std::string, uint32_t>& byName, RoomDescription& room) {
    r_.object(v, path, {"quad", "name", "u", "v", "material", "patch_size"});
    const std::string quadName = r_.string(r_.required(v, path, "quad"), join(path, "quad"));
    const auto it = byName.find(quadName);
    if (it == byName.end()) r_.fail(join(path, "quad"), "no quad named \"" + quadName + "\"");
    Quad& q = room.quads[it->second];
    Region region;
    region.name = r_.string(r_.required(v, path, "name"), join(path, "name"));
    const double lu = glm::length(q.edgeU), lv = glm::length(q.edgeV);
    const auto [u0, u1] = r_.range(r_.required(v, path, "u"), join(path, "u"));
    const auto [v0, v1] = r_.range(r_.required(v, path, "v"), join(path, "v"));
    if (u0 < 0 || u1 > lu) {
      r_.fail(join(path, "u"), "must lie within [0, " + std::to_string(lu) + "] m");
    }
    if (v0 < 0 || v1 > lv) {
      r_.fail(join(path, "v"), "must lie within [0, " + std::to_string(lv) + "] m");
    }
    region.s0 = u0 / lu;
    region.s1 = u1 / lu;
    region.t0 = v0 / lv;
    region.t1 = v1 / lv;
    region.material = material(r_.required(v, path, "material"), join(path, "material"));
    if (const json* ps = r_.optional(v, "patch_size")) {
      region.patchSize = r_.positive(*ps, join(path, "patch_size"));
    }
    // The patch mesh gives each cell one material; overlapping regions would make that
    // depend on their order.
    for (const Region& other : q.regions) {
      if (region.s0 < other.s1 && other.s0 < region.s1 && region.t0 < other.t1 &&
          other.t0 < region.t1) {
        r_.fail(path, "overlaps region \"" + other.name + "\" of quad \"" + quadName + "\"");
      }
    }
    q.regions.push_back(std::move(region));
  }

  Product parseProduct(const json& v, const std::string& path) {
    r_.object(v, path,
              {"name", "model", "scale", "rotate_y_deg", "rest_on_floor", "colour",
               "proxy_triangles", "specular", "specular_exponent"});
    Product p;
    p.name = r_.string(r_.required(v, path, "name"), join(path, "name"));
    const std::string model = r_.string(r_.required(v, path, "model"), join(path, "model"));
    p.model = path_.parent_path() / model;
    if (const json* s = r_.optional(v, "scale")) p.scale = r_.positive(*s, join(path, "scale"));
    if (const json* rot = r_.optional(v, "rotate_y_deg")) {
      p.rotateYDegrees = r_.number(*rot, join(path, "rotate_y_deg"));
    }
    if (const json* rest = r_.optional(v, "rest_on_floor")) {
      p.restOnFloor = r_.boolean(*rest, join(path, "rest_on_floor"));
    }
    if (const json* n = r_.optional(v, "proxy_triangles")) {
      p.proxyTriangles = r_.count(*n, join(path, "proxy_triangles"), 4, 100000);
    }
    std::string ext = p.model.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const bool gltf = ext == ".gltf" || ext == ".glb";
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
        p.mesh = loadMesh(p.model);
      }
#else
      p.mesh = loadMesh(p.model);
#endif
    } catch (const MeshError& e) {
      r_.fail(join(path, "model"), e.what());
    }
    if (const json* c = r_.optional(v, "colour")) {
      p.reflectance = r_.colour(*c, join(path, "colour"));
    } else if (!gltf) {
      r_.required(v, path, "colour");  // OBJ/PLY carry no material
    }
    if (const json* c = r_.optional(v, "specular")) {
      p.specular = r_.colour(*c, join(path, "specular"));
    }
    if (const json* e = r_.optional(v, "specular_exponent")) {
      p.specularExponent = r_.number(*e, join(path, "specular_exponent"));
      if (!(p.specularExponent >= 0 && p.specularExponent <= 1e6)) {
        r_.fail(join(path, "specular_exponent"), "must be in [0, 1e6]");
      }
    }
    placeInProductSpace(p);
    p.proxy = simplifyForShadows(p.mesh, p.proxyTriangles);
    return p;
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
    const Aabb b = p.mesh.bounds();
    const glm::dvec3 shift(-b.centre().x, p.restOnFloor ? -b.min.y : 0.0, -b.centre().z);
    for (glm::dvec3& q : p.mesh.positions) q += shift;
  }

  const Reader& r_;
  std::filesystem::path path_;
  std::map<std::string, Material> materials_;
};

}  // namespace

SceneDescription parseSceneFile(std::string_view text, const std::filesystem::path& path) {
  const Reader reader(path.string());
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    reader.fail("", std::string("not valid JSON: ") + e.what());
  }
  return SceneParser(reader, path).parse(doc);
}

SceneDescription loadSceneFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneFileError(path.string() + ": cannot open file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw SceneFileError(path.string() + ": read error");
  return parseSceneFile(text, path);
}

}  // namespace penumbra::scene
