#include "scene/mesh_io.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <system_error>

#include "core/json_reader.h"
#include "core/regular_file.h"
#include "scene/gltf_io.h"
#include "scene/mesh_attributes.h"
#include "scene/texture.h"

namespace penumbra::scene {

Aabb TriangleMesh::bounds() const {
  Aabb b = Aabb::emptyBox();
  for (const glm::dvec3& p : positions) b.extend(p);
  return b;
}

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& where, const std::string& what) {
  throw MeshError(name + ": " + (where.empty() ? "" : where + ": ") + what);
}

std::string lineRef(size_t line) {
  return "line " + std::to_string(line);
}

// Whitespace-separated tokens of one line, at most `maxTokens` + 1 of them: a caller that
// gets more than maxTokens refuses the line, so a 200 MB line of numbers costs no more than
// a short one.
std::vector<std::string_view> tokenize(std::string_view line, size_t maxTokens) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size() && out.size() <= maxTokens) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\v' ||
                               line[i] == '\f' || line[i] == '\r')) {
      ++i;
    }
    const size_t start = i;
    while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\v' ||
                                line[i] == '\f' || line[i] == '\r')) {
      ++i;
    }
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// from_chars is locale-independent (strtod is not: a kiosk with a German locale would
// read "0.5" as 0) but rejects a leading '+', which some exporters write.
std::optional<double> parseDouble(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<int64_t> parseInt(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// Splits `text` into lines without their terminators; the last line may lack '\n'.
template <typename F>
void forEachLine(std::string_view text, F&& f) {
  size_t lineNo = 1, pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    f(lineNo++, text.substr(pos, end - pos));
    pos = end + 1;
  }
}

// A coordinate within the limits of mesh_io.h (the message prints the value as written).
void checkCoordinate(double v, const std::string& name, const std::string& where) {
  if (!std::isfinite(v)) fail(name, where, "non-finite coordinate '" + core::formatNumber(v) + "'");
  if (std::abs(v) > kMaxModelCoordinate) {
    fail(name, where,
         "coordinate " + core::formatNumber(v) +
             " is outside [-1e6, 1e6] (model units: a kilometre in millimetres is the largest " +
             "model read)");
  }
}

void checkVertexCount(size_t count, const std::string& name, const std::string& where) {
  if (count > kMaxMeshVertices) {
    fail(name, where,
         std::to_string(count) + " vertices, more than the " + std::to_string(kMaxMeshVertices) +
             " a model may have");
  }
}

void checkTriangleCount(size_t count, const std::string& name, const std::string& where) {
  if (count > kMaxMeshTriangles) {
    fail(name, where,
         "more than " + std::to_string(kMaxMeshTriangles) +
             " triangles (the most a product model may have)");
  }
}

void checkFaceCorners(size_t corners, const std::string& name, const std::string& where) {
  if (corners > kMaxFaceCorners) {
    fail(name, where,
         "face with more than the " + std::to_string(kMaxFaceCorners) +
             " corners a polygon may have");
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// OBJ

namespace {

// Blender's default base colour (its Principled BSDF's), for faces without a material in a
// file whose other faces have one.
constexpr double kDefaultReflectance = 0.8;

// An MTL material: Kd and its map_Kd.
struct ObjMaterial {
  glm::dvec3 kd{kDefaultReflectance};
  int texture = -1;  // index into ObjReader::textures_, -1: none (or not decodable here)
  TextureWrap wrap = TextureWrap::kRepeat;
  glm::dvec2 offset{0.0}, scale{1.0};  // map_Kd -o and -s: uv' = uv * scale + offset
};

// map_Kd options (MTL spec, "Options for texture map statements"): how many numbers each
// takes (-o, -s and -t one to three), or 0 for the one word the on/off and name options take.
int mapOptionNumbers(std::string_view option) {
  if (option == "-o" || option == "-s" || option == "-t") return 3;
  if (option == "-mm") return 2;
  if (option == "-boost" || option == "-texres" || option == "-bm") return 1;
  if (option == "-clamp" || option == "-blendu" || option == "-blendv" || option == "-cc" ||
      option == "-type" || option == "-imfchan") {
    return 0;
  }
  return -1;
}

class ObjReader {
 public:
  ObjReader(const std::string& name, const MeshOptions& options)
      : name_(name), options_(options), folder_(std::filesystem::path(name).parent_path()) {}

  TriangleMesh parse(std::string_view text) {
    forEachLine(text, [&](size_t lineNo, std::string_view line) { statement(lineNo, line); });
    if (soup_.faceCount() == 0) fail(name_, "", "no faces");
    assignAttributes();
    TriangleMesh mesh = buildTriangleMesh(soup_, options_.creaseAngleDegrees);
    mesh.warnings = std::move(warnings_);
    return mesh;
  }

 private:
  struct PendingCorner {
    uint32_t uv;   // kNoAttribute: none
    int material;  // -1: none
  };

  void statement(size_t lineNo, std::string_view line) {
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    const std::vector<std::string_view> tok = tokenize(line, kMaxFaceCorners + 1);
    if (tok.empty()) return;
    const std::string where = lineRef(lineNo);
    if (tok[0] == "v") {
      // x y z, optionally w or an r g b vertex colour: all must be numbers.
      if (tok.size() < 4) fail(name_, where, "vertex needs x, y and z");
      soup_.positions.push_back(numbers<3>(tok, where));
      checkVertexCount(soup_.positions.size(), name_, where);
    } else if (tok[0] == "vn") {
      if (tok.size() != 4) fail(name_, where, "normal needs x, y and z");
      const glm::dvec3 n = numbers<3>(tok, where);
      const double length = glm::length(n);
      if (!(length > 0) || !std::isfinite(length)) fail(name_, where, "normal of zero length");
      soup_.normals.push_back(n / length);
      checkVertexCount(soup_.normals.size(), name_, where);
    } else if (tok[0] == "vt") {
      if (tok.size() < 2 || tok.size() > 4)
        fail(name_, where, "texture coordinate needs u [v [w]]");
      const glm::dvec3 t = numbers<3>(tok, where);
      uvs_.emplace_back(t.x, t.y);
      checkVertexCount(uvs_.size(), name_, where);
    } else if (tok[0] == "f") {
      face(tok, where);
    } else if (tok[0] == "s") {
      if (tok.size() != 2) fail(name_, where, "s needs one group number or 'off'");
      if (tok[1] == "off") {
        group_ = 0;
      } else {
        const std::optional<int64_t> g = parseInt(tok[1]);
        if (!g || *g < 0 || *g > int64_t{UINT32_MAX}) {
          fail(name_, where, "bad smoothing group '" + std::string(tok[1]) + "'");
        }
        group_ = static_cast<uint32_t>(*g);
      }
      soup_.smoothingGroups = true;
    } else if (tok[0] == "mtllib") {
      if (tok.size() < 2) fail(name_, where, "mtllib needs a file name");
      // The MTL spec allows several files on one line.
      for (size_t k = 1; k < tok.size(); ++k) readMtl(folder_ / std::string(tok[k]), where);
    } else if (tok[0] == "usemtl") {
      if (tok.size() < 2) fail(name_, where, "usemtl needs a material name");
      const std::string material = restOfLine(line, tok[1]);
      const auto it = materialIndex_.find(material);
      if (it == materialIndex_.end()) {
        if (mtlFiles_.empty()) {
          // No mtllib at all: the model was exported without its materials. Its colour
          // comes from the scene file, as for a model without usemtl.
          if (!warnedNoMtllib_) {
            warnings_.push_back(name_ + ": " + where + ": usemtl " + material +
                                " but no mtllib: materials ignored");
            warnedNoMtllib_ = true;
          }
          material_ = -1;
          return;
        }
        fail(name_, where, "usemtl: no material named '" + material + "' in " + mtlFiles_);
      }
      material_ = it->second;
      usedMaterials_ = true;
    }
    // Everything else (g, o, l, p, ...) carries nothing the pipeline uses.
  }

  template <int N>
  glm::dvec3 numbers(const std::vector<std::string_view>& tok, const std::string& where) {
    glm::dvec3 p(0.0);
    for (size_t k = 1; k < tok.size(); ++k) {
      const std::optional<double> v = parseDouble(tok[k]);
      if (!v) fail(name_, where, "bad number '" + std::string(tok[k]) + "'");
      checkCoordinate(*v, name_, where);
      if (k <= N) p[static_cast<int>(k - 1)] = *v;
    }
    return p;
  }

  // A 1-based or negative (relative: -1 is the last defined so far) index into a list of
  // `count` entries of `what` (`whats` in the plural).
  uint32_t resolve(std::string_view ref, size_t count, const char* what, const char* whats,
                   std::string_view corner, const std::string& where) const {
    const std::optional<int64_t> idx = parseInt(ref);
    if (!idx)
      fail(name_, where, std::string("bad ") + what + " index '" + std::string(corner) + "'");
    const int64_t n = static_cast<int64_t>(count);
    const int64_t resolved = *idx > 0 ? *idx - 1 : n + *idx;
    if (*idx == 0 || resolved < 0 || resolved >= n) {
      fail(name_, where,
           std::string(what) + " index " + std::to_string(*idx) + " out of range (" +
               std::to_string(count) + " " + whats + " defined so far)");
    }
    return static_cast<uint32_t>(resolved);
  }

  void face(const std::vector<std::string_view>& tok, const std::string& where) {
    if (tok.size() < 4) {
      fail(name_, where, "face needs at least 3 vertices, has " + std::to_string(tok.size() - 1));
    }
    checkFaceCorners(tok.size() - 1, name_, where);
    checkTriangleCount(triangles_ + tok.size() - 3, name_, where);
    triangles_ += tok.size() - 3;
    for (size_t k = 1; k < tok.size(); ++k) {
      const std::string_view c = tok[k];
      const size_t slash1 = c.find('/');
      const size_t slash2 = slash1 == std::string_view::npos ? slash1 : c.find('/', slash1 + 1);
      soup_.cornerPosition.push_back(
          resolve(c.substr(0, slash1), soup_.positions.size(), "vertex", "vertices", c, where));
      uint32_t uv = kNoAttribute, normal = kNoAttribute;
      if (slash1 != std::string_view::npos) {
        const std::string_view t =
            c.substr(slash1 + 1, slash2 == std::string_view::npos ? std::string_view::npos
                                                                  : slash2 - slash1 - 1);
        if (!t.empty())
          uv = resolve(t, uvs_.size(), "texture coordinate", "texture coordinates", c, where);
        if (slash2 != std::string_view::npos) {
          normal =
              resolve(c.substr(slash2 + 1), soup_.normals.size(), "normal", "normals", c, where);
        }
      }
      soup_.cornerNormal.push_back(normal);
      pending_.push_back({uv, material_});
    }
    soup_.faceGroup.push_back(group_);
    soup_.endFace();
  }

  // The text of `line` from token `first` to its end, trailing blanks removed (names with
  // spaces).
  static std::string restOfLine(std::string_view line, std::string_view first) {
    std::string_view rest = line.substr(static_cast<size_t>(first.data() - line.data()));
    while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t' || rest.back() == '\r')) {
      rest.remove_suffix(1);
    }
    return std::string(rest);
  }

  std::string readFile(const std::filesystem::path& path, const std::string& context) const {
    try {
      return options_.readFile(path);
    } catch (const std::exception& e) {
      throw MeshError(context + ": " + e.what());
    }
  }

  void readMtl(const std::filesystem::path& path, const std::string& where) {
    const std::string mtlName = path.string();
    const std::string text = readFile(path, name_ + ": " + where + ": mtllib");
    mtlFiles_ += (mtlFiles_.empty() ? "" : ", ") + mtlName;
    int current = -1;
    forEachLine(text, [&](size_t lineNo, std::string_view line) {
      if (const size_t hash = line.find('#'); hash != std::string_view::npos) {
        line = line.substr(0, hash);
      }
      const std::vector<std::string_view> tok = tokenize(line, 64);
      if (tok.empty()) return;
      const std::string at = lineRef(lineNo);
      if (tok.size() > 64) fail(mtlName, at, "more than 64 values on one line");
      if (tok[0] == "newmtl") {
        if (tok.size() < 2) fail(mtlName, at, "newmtl needs a name");
        if (materials_.size() >= kMaxMaterials) {
          fail(mtlName, at, "more than " + std::to_string(kMaxMaterials) + " materials");
        }
        current = static_cast<int>(materials_.size());
        materials_.emplace_back();
        materialIndex_[restOfLine(line, tok[1])] = current;  // a later definition wins
        return;
      }
      const bool kd = tok[0] == "Kd", map = tok[0] == "map_Kd";
      if (!kd && !map) return;  // Ka, Ks, Ns, d, illum, map_Bump, ...: not used
      if (current < 0) fail(mtlName, at, std::string(tok[0]) + " before newmtl");
      ObjMaterial& m = materials_[size_t(current)];
      if (kd) {
        if (tok.size() != 2 && tok.size() != 4) {
          fail(mtlName, at, "Kd needs r [g b] (spectral and xyz forms are not read)");
        }
        for (size_t k = 1; k < tok.size(); ++k) {
          const std::optional<double> v = parseDouble(tok[k]);
          if (!v || !(*v >= 0 && *v <= 1)) {
            fail(mtlName, at, "Kd value '" + std::string(tok[k]) + "' is not a number in [0, 1]");
          }
          m.kd[static_cast<int>(k - 1)] = *v;
        }
        if (tok.size() == 2) m.kd = glm::dvec3(m.kd.x);  // "Kd r": g = b = r
        return;
      }
      textureMap(m, line, tok, path, at);
    });
  }

  void textureMap(ObjMaterial& m, std::string_view line, const std::vector<std::string_view>& tok,
                  const std::filesystem::path& mtl, const std::string& at) {
    const std::string mtlName = mtl.string();
    size_t k = 1;
    while (k < tok.size() && tok[k].size() > 1 && tok[k][0] == '-') {
      const std::string_view option = tok[k++];
      const int maxNumbers = mapOptionNumbers(option);
      if (maxNumbers < 0) fail(mtlName, at, "map_Kd: unknown option '" + std::string(option) + "'");
      if (k >= tok.size()) fail(mtlName, at, "map_Kd " + std::string(option) + ": no value");
      if (maxNumbers == 0) {
        if (option == "-clamp") {
          if (tok[k] != "on" && tok[k] != "off") fail(mtlName, at, "map_Kd -clamp: on or off");
          m.wrap = tok[k] == "on" ? TextureWrap::kClampToEdge : TextureWrap::kRepeat;
        }
        ++k;
        continue;
      }
      std::vector<double> values;
      while (k < tok.size() && int(values.size()) < maxNumbers) {
        const std::optional<double> v = parseDouble(tok[k]);
        if (!v) break;
        if (!(std::abs(*v) <= kMaxModelCoordinate)) {
          fail(mtlName, at, "map_Kd " + std::string(option) + ": number out of range");
        }
        values.push_back(*v);
        ++k;
      }
      if (values.empty()) fail(mtlName, at, "map_Kd " + std::string(option) + ": bad number");
      if (option == "-o") m.offset = glm::dvec2(values[0], values.size() > 1 ? values[1] : 0.0);
      if (option == "-s") m.scale = glm::dvec2(values[0], values.size() > 1 ? values[1] : 1.0);
    }
    if (k >= tok.size()) fail(mtlName, at, "map_Kd needs a file name");
    const std::filesystem::path file = mtl.parent_path() / restOfLine(line, tok[k]);
    m.texture = texture(file, mtlName + ": " + at + ": map_Kd");
  }

  // The texture at `file`, decoded once per file; -1 (with a warning) when the build has no
  // decoder for its format.
  int texture(const std::filesystem::path& file, const std::string& context) {
    const std::string key = file.string();
    if (const auto it = textureIndex_.find(key); it != textureIndex_.end()) return it->second;
    const std::string bytes = readFile(file, context);
    std::optional<Texture> t;
    try {
      t = decodeTexture(bytes, key);
    } catch (const TextureError& e) {
      throw MeshError(context + ": " + e.what());
    }
    int index = -1;
    if (t) {
      index = static_cast<int>(textures_.size());
      textures_.push_back(std::move(*t));
    } else {
      warnings_.push_back(context + ": " + key +
                          ": no decoder for this image format in this build (PNG and PPM are "
                          "read everywhere, JPEG with PENUMBRA_WITH_GLTF); the material's Kd "
                          "is used");
    }
    textureIndex_[key] = index;
    return index;
  }

  // Per corner: the attribute (material, uv) and its reflectance, when any face has a
  // material.
  void assignAttributes() {
    const size_t corners = soup_.cornerPosition.size();
    if (!usedMaterials_) {
      soup_.cornerAttribute.assign(corners, kNoAttribute);
      return;
    }
    std::map<std::pair<int, uint32_t>, uint32_t> ids;
    size_t withoutMaterial = 0, withoutUv = 0;
    soup_.cornerAttribute.resize(corners);
    for (size_t c = 0; c < corners; ++c) {
      const PendingCorner& p = pending_[c];
      const int material = p.material;
      // Only a textured material reads the uv: the key ignores it otherwise.
      const bool textured = material >= 0 && materials_[size_t(material)].texture >= 0;
      const uint32_t uv = textured ? p.uv : kNoAttribute;
      const auto [it, added] = ids.emplace(std::pair(material, uv), uint32_t(ids.size()));
      soup_.cornerAttribute[c] = it->second;
      if (!added) continue;
      if (material < 0) {
        ++withoutMaterial;
        soup_.reflectances.emplace_back(kDefaultReflectance);
        continue;
      }
      const ObjMaterial& m = materials_[size_t(material)];
      glm::dvec3 r = m.kd;
      if (textured) {
        if (uv == kNoAttribute) {
          ++withoutUv;
        } else {
          // OBJ's v points up, the image's rows down.
          const glm::dvec2 t = uvs_[uv] * m.scale + m.offset;
          r *= sampleBilinear(textures_[size_t(m.texture)], t.x, 1.0 - t.y, m.wrap, m.wrap);
        }
      }
      soup_.reflectances.push_back(glm::clamp(r, 0.0, 1.0));
    }
    if (withoutMaterial > 0) {
      warnings_.push_back(name_ + ": faces before the first usemtl have no material: shaded " +
                          "with Blender's default 0.8 grey");
    }
    if (withoutUv > 0) {
      warnings_.push_back(name_ + ": corners without a texture coordinate on a textured " +
                          "material: shaded with its Kd alone");
    }
  }

  static constexpr size_t kMaxMaterials = 65536;

  const std::string& name_;
  const MeshOptions& options_;
  std::filesystem::path folder_;
  PolygonSoup soup_;
  std::vector<glm::dvec2> uvs_;
  std::vector<PendingCorner> pending_;
  std::vector<ObjMaterial> materials_;
  std::map<std::string, int> materialIndex_;
  std::vector<Texture> textures_;
  std::map<std::string, int> textureIndex_;
  std::string mtlFiles_;
  std::vector<std::string> warnings_;
  size_t triangles_ = 0;
  uint32_t group_ = 0;
  int material_ = -1;
  bool usedMaterials_ = false, warnedNoMtllib_ = false;
};

}  // namespace

TriangleMesh parseObj(std::string_view text, const std::string& name, const MeshOptions& options) {
  return ObjReader(name, options).parse(text);
}

// ---------------------------------------------------------------------------------------
// PLY

namespace {

enum class PlyType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

std::optional<PlyType> plyType(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::kInt8;
  if (s == "uchar" || s == "uint8") return PlyType::kUInt8;
  if (s == "short" || s == "int16") return PlyType::kInt16;
  if (s == "ushort" || s == "uint16") return PlyType::kUInt16;
  if (s == "int" || s == "int32") return PlyType::kInt32;
  if (s == "uint" || s == "uint32") return PlyType::kUInt32;
  if (s == "float" || s == "float32") return PlyType::kFloat32;
  if (s == "double" || s == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool plyIsInteger(PlyType t) {
  return t != PlyType::kFloat32 && t != PlyType::kFloat64;
}

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyType countType = PlyType::kUInt8;
  PlyType type = PlyType::kFloat32;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
  size_t headerLine = 0;  // of its `element` line, for messages

  // The fewest bytes one record can take: binary, a scalar's size and a list's count (the
  // list may be empty); ASCII, a line of one character and its newline.
  size_t minimumRecordBytes(bool binary) const {
    if (!binary) return 2;
    size_t bytes = 0;
    for (const PlyProperty& p : properties) bytes += plySize(p.isList ? p.countType : p.type);
    return bytes;
  }
};

// One ASCII line holds one record: its scalars and lists of at most kMaxFaceCorners values.
constexpr size_t kMaxPlyLineValues = 4 * kMaxFaceCorners;

// Every element's count is bounded before a record is read: by the stated limits (vertices,
// faces, and kMaxMeshVertices for any other element, which the reader only skips) and by
// the bytes actually present, since each record takes at least minimumRecordBytes(). A
// header announcing 10^12 records of an element without properties is refused here
// instead of being looped over.
void checkElementCounts(const std::vector<PlyElement>& elements, bool binary, size_t bodyBytes,
                        const std::string& name) {
  // ASCII: the last line may lack its newline.
  size_t remaining = binary ? bodyBytes : bodyBytes + 1;
  for (const PlyElement& e : elements) {
    const std::string where = lineRef(e.headerLine) + ": element " + e.name;
    const size_t limit = e.name == "face" ? kMaxMeshTriangles : kMaxMeshVertices;
    if (e.count > limit) {
      fail(name, where,
           std::to_string(e.count) + " records, more than the " + std::to_string(limit) +
               " a model may have");
    }
    const size_t record = e.minimumRecordBytes(binary);
    if (record > 0 && e.count > remaining / record) {
      fail(name, where,
           std::to_string(e.count) + " records of at least " + std::to_string(record) +
               " bytes do not fit in the " + std::to_string(remaining) + " bytes left in the file");
    }
    remaining -= e.count * record;
  }
}

template <typename T>
T loadLittleEndian(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

// Reads the values of one element instance either from binary data or from one line of
// ASCII tokens; every value is widened to double (exact for all PLY scalar types).
class PlyReader {
 public:
  PlyReader(std::string_view body, bool binary, const std::string& name)
      : body_(body), binary_(binary), name_(name) {}

  // Positions at the next instance of element `elem` (index `i`).
  void beginInstance(const std::string& elem, size_t i) {
    where_ = elem + " " + std::to_string(i);
    if (binary_) return;
    // ASCII: one instance per line; blank lines are skipped.
    tokens_.clear();
    next_ = 0;
    while (pos_ < body_.size() && tokens_.empty()) {
      size_t end = body_.find('\n', pos_);
      if (end == std::string_view::npos) end = body_.size();
      tokens_ = tokenize(body_.substr(pos_, end - pos_), kMaxPlyLineValues);
      pos_ = end + 1;
      ++line_;
    }
    if (tokens_.size() > kMaxPlyLineValues) {
      fail(name_, location(),
           "more than " + std::to_string(kMaxPlyLineValues) + " values on one line");
    }
    if (tokens_.empty()) fail(name_, where_, "unexpected end of file");
  }

  void endInstance() {
    if (!binary_ && next_ != tokens_.size()) {
      fail(name_, location(),
           std::to_string(tokens_.size() - next_) + " extra value(s) at the end of the line");
    }
  }

  double read(PlyType t) {
    if (binary_) {
      const size_t n = plySize(t);
      if (body_.size() - pos_ < n) {
        fail(name_, where_,
             "truncated binary data (" + std::to_string(body_.size()) + " bytes after the header)");
      }
      const char* p = body_.data() + pos_;
      pos_ += n;
      switch (t) {
        case PlyType::kInt8:
          return loadLittleEndian<int8_t>(p);
        case PlyType::kUInt8:
          return loadLittleEndian<uint8_t>(p);
        case PlyType::kInt16:
          return loadLittleEndian<int16_t>(p);
        case PlyType::kUInt16:
          return loadLittleEndian<uint16_t>(p);
        case PlyType::kInt32:
          return loadLittleEndian<int32_t>(p);
        case PlyType::kUInt32:
          return loadLittleEndian<uint32_t>(p);
        case PlyType::kFloat32:
          return loadLittleEndian<float>(p);
        case PlyType::kFloat64:
          return loadLittleEndian<double>(p);
      }
      return 0;
    }
    if (next_ >= tokens_.size()) fail(name_, location(), "too few values on the line");
    const std::string_view tok = tokens_[next_++];
    if (plyIsInteger(t)) {
      const std::optional<int64_t> v = parseInt(tok);
      if (!v) fail(name_, location(), "bad integer '" + std::string(tok) + "'");
      return static_cast<double>(*v);
    }
    const std::optional<double> v = parseDouble(tok);
    if (!v) fail(name_, location(), "bad number '" + std::string(tok) + "'");
    return *v;
  }

  // After the last element: nothing but whitespace may follow.
  void finish() {
    if (binary_) {
      if (pos_ != body_.size()) {
        fail(name_, "",
             std::to_string(body_.size() - pos_) + " unexpected bytes after the last element");
      }
      return;
    }
    if (pos_ < body_.size() &&
        body_.find_first_not_of(" \t\r\n\v\f", pos_) != std::string_view::npos) {
      fail(name_, "", "unexpected content after the last element");
    }
  }

  // "line N (vertex i)" for ASCII, "vertex i" for binary.
  std::string location() const {
    return binary_ ? where_ : lineRef(headerLines_ + line_) + " (" + where_ + ")";
  }
  void setHeaderLines(size_t n) { headerLines_ = n; }

 private:
  std::string_view body_;
  bool binary_;
  const std::string& name_;
  size_t pos_ = 0;
  std::string where_;
  std::vector<std::string_view> tokens_;
  size_t next_ = 0;
  size_t line_ = 0;
  size_t headerLines_ = 0;
};

}  // namespace

TriangleMesh parsePly(std::string_view bytes, const std::string& name, const MeshOptions& options) {
  // Header: ASCII lines up to end_header; the body starts after its '\n'.
  std::vector<PlyElement> elements;
  std::optional<bool> binary;
  size_t pos = 0, lineNo = 0;
  bool ended = false;
  while (pos < bytes.size() && !ended) {
    size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) end = bytes.size();
    const std::string_view line = bytes.substr(pos, end - pos);
    pos = std::min(end + 1, bytes.size());
    ++lineNo;
    // A header line has at most 5 tokens; comments may be longer and are skipped.
    const std::vector<std::string_view> tok = tokenize(line, 8);
    const std::string where = lineRef(lineNo);
    if (lineNo == 1) {
      if (tok.size() != 1 || tok[0] != "ply") fail(name, where, "not a PLY file (no 'ply' magic)");
      continue;
    }
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() != 3 || tok[2] != "1.0") fail(name, where, "bad format line");
      if (tok[1] == "ascii") {
        binary = false;
      } else if (tok[1] == "binary_little_endian") {
        binary = true;
      } else {
        fail(name, where,
             "unsupported format '" + std::string(tok[1]) +
                 "' (ascii and binary_little_endian are read)");
      }
    } else if (tok[0] == "element") {
      const std::optional<int64_t> count = tok.size() == 3 ? parseInt(tok[2]) : std::nullopt;
      if (!count || *count < 0) fail(name, where, "bad element line");
      elements.push_back(PlyElement{std::string(tok[1]), static_cast<size_t>(*count), {}, lineNo});
    } else if (tok[0] == "property") {
      if (elements.empty()) fail(name, where, "property before any element");
      PlyProperty prop;
      if (tok.size() == 5 && tok[1] == "list") {
        const auto countType = plyType(tok[2]), type = plyType(tok[3]);
        if (!countType || !type) fail(name, where, "unknown property type");
        if (!plyIsInteger(*countType)) fail(name, where, "list count type must be an integer");
        prop = PlyProperty{std::string(tok[4]), true, *countType, *type};
      } else if (tok.size() == 3) {
        const auto type = plyType(tok[1]);
        if (!type) fail(name, where, "unknown property type '" + std::string(tok[1]) + "'");
        prop = PlyProperty{std::string(tok[2]), false, PlyType::kUInt8, *type};
      } else {
        fail(name, where, "bad property line");
      }
      elements.back().properties.push_back(prop);
    } else if (tok[0] == "end_header") {
      ended = true;
    } else {
      fail(name, where, "unknown header keyword '" + std::string(tok[0]) + "'");
    }
  }
  if (lineNo == 0) fail(name, "", "empty file");
  if (!ended) fail(name, "", "header has no end_header");
  if (!binary) fail(name, "", "header has no format line");

  // Where x, y, z and the face indices sit among the element's properties.
  const PlyElement* vertexElem = nullptr;
  const PlyElement* faceElem = nullptr;
  int xyz[3] = {-1, -1, -1};
  int faceList = -1;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") {
      vertexElem = &e;
      for (size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        for (int k = 0; k < 3; ++k) {
          if (prop.name == std::string(1, static_cast<char>('x' + k))) {
            if (prop.isList) fail(name, "vertex", "property " + prop.name + " is a list");
            xyz[k] = static_cast<int>(p);
          }
        }
      }
      for (int k = 0; k < 3; ++k) {
        if (xyz[k] < 0) {
          fail(name, "vertex", std::string("no property ") + static_cast<char>('x' + k));
        }
      }
    } else if (e.name == "face") {
      faceElem = &e;
      for (size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        if (prop.name == "vertex_indices" || prop.name == "vertex_index") {
          if (!prop.isList || !plyIsInteger(prop.type)) {
            fail(name, "face", prop.name + " must be a list of integers");
          }
          faceList = static_cast<int>(p);
        }
      }
      if (faceList < 0) fail(name, "face", "no vertex_indices list");
    }
  }
  if (!vertexElem) fail(name, "", "no vertex element");
  if (!faceElem) fail(name, "", "no face element");
  checkElementCounts(elements, *binary, bytes.size() - pos, name);

  TriangleMesh mesh;
  // Faces may precede the vertices in PLY, so indices are checked after reading.
  struct Face {
    size_t first, count;
    std::string location;
  };
  std::vector<int64_t> faceIndices;
  std::vector<Face> faces;
  PlyReader reader(bytes.substr(pos), *binary, name);
  reader.setHeaderLines(lineNo);
  size_t triangles = 0;
  for (const PlyElement& e : elements) {
    const bool isVertex = &e == vertexElem, isFace = &e == faceElem;
    // The count was bounded by checkElementCounts().
    if (isVertex) mesh.positions.reserve(e.count);
    for (size_t i = 0; i < e.count; ++i) {
      reader.beginInstance(e.name, i);
      glm::dvec3 p(0.0);
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        if (prop.isList) {
          const double n = reader.read(prop.countType);
          if (n < 0) fail(name, reader.location(), "negative list length");
          const bool keep = isFace && static_cast<int>(k) == faceList;
          if (keep) {
            if (n < 3) {
              fail(
                  name, reader.location(),
                  "face needs at least 3 vertices, has " + std::to_string(static_cast<int64_t>(n)));
            }
            checkFaceCorners(static_cast<size_t>(n), name, reader.location());
            triangles += static_cast<size_t>(n) - 2;
            checkTriangleCount(triangles, name, reader.location());
            faces.push_back(Face{faceIndices.size(), static_cast<size_t>(n), reader.location()});
          }
          for (size_t j = 0; j < static_cast<size_t>(n); ++j) {
            const double v = reader.read(prop.type);
            if (keep) faceIndices.push_back(static_cast<int64_t>(v));
          }
        } else {
          const double v = reader.read(prop.type);
          if (isVertex) {
            for (int c = 0; c < 3; ++c) {
              if (static_cast<int>(k) != xyz[c]) continue;
              checkCoordinate(v, name, reader.location());
              p[c] = v;
            }
          }
        }
      }
      reader.endInstance();
      if (isVertex) mesh.positions.push_back(p);
    }
  }
  reader.finish();

  const int64_t vertexCount = static_cast<int64_t>(mesh.positions.size());
  // PLY gives no normals the pipeline reads: they are split by crease angle.
  PolygonSoup soup;
  soup.positions = std::move(mesh.positions);
  for (const Face& f : faces) {
    for (size_t j = 0; j < f.count; ++j) {
      const int64_t idx = faceIndices[f.first + j];
      if (idx < 0 || idx >= vertexCount) {
        fail(name, f.location,
             "vertex index " + std::to_string(idx) + " out of range (" +
                 std::to_string(vertexCount) + " vertices)");
      }
      soup.cornerPosition.push_back(static_cast<uint32_t>(idx));
    }
    soup.endFace();
  }
  if (soup.faceCount() == 0) fail(name, "", "no faces");
  soup.cornerNormal.assign(soup.cornerPosition.size(), kNoAttribute);
  soup.cornerAttribute.assign(soup.cornerPosition.size(), kNoAttribute);
  return buildTriangleMesh(soup, options.creaseAngleDegrees);
}

// ---------------------------------------------------------------------------------------
// Files

std::string MeshOptions::readModelFile(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes =
      core::readRegularFile(path, kMaxModelFileBytes, "a model file", core::throwAs<MeshError>);
  return std::string(bytes.begin(), bytes.end());
}

TriangleMesh loadMesh(const std::filesystem::path& path, const MeshOptions& options) {
  const std::string name = path.string();
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") {
#ifdef PENUMBRA_HAVE_GLTF
    return loadGltf(path).mesh;
#else
    fail(name, "", "this build has no glTF support (PENUMBRA_WITH_GLTF)");
#endif
  }
  if (ext != ".obj" && ext != ".ply") {
    fail(name, "", "unknown mesh format '" + ext + "' (expected .obj, .ply, .gltf or .glb)");
  }
  if (!(options.creaseAngleDegrees >= 0 && options.creaseAngleDegrees <= 180)) {
    fail(name, "", "crease angle must be in [0, 180] degrees");
  }
  // Regular files of bounded size only: a product path pointing at /dev/zero or a folder is
  // refused before a byte is read.
  const std::string bytes = core::readTextFile(path, core::throwAs<MeshError>, kMaxModelFileBytes);
  return ext == ".obj" ? parseObj(bytes, name, options) : parsePly(bytes, name, options);
}

void saveObj(const TriangleMesh& mesh, const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(path.string(), "", "cannot create file");
  char buf[64];
  // Shortest round-trip form: the file reloads to the same doubles.
  auto number = [&](double v) {
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out << ' ' << std::string_view(buf, static_cast<size_t>(r.ptr - buf));
  };
  for (const glm::dvec3& p : mesh.positions) {
    out << 'v';
    number(p.x);
    number(p.y);
    number(p.z);
    out << '\n';
  }
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    out << "f " << mesh.indices[3 * t] + 1 << ' ' << mesh.indices[3 * t + 1] + 1 << ' '
        << mesh.indices[3 * t + 2] + 1 << '\n';
  }
  out.flush();
  if (!out) fail(path.string(), "", "write error");
}

}  // namespace penumbra::scene
