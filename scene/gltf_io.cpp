#include "scene/gltf_io.h"

#include "core/regular_file.h"
#include "scene/mesh_attributes.h"
#include "scene/texture.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace penumbra::scene {

ProductMaterial mapMetallicRoughness(const glm::dvec3& baseColour, double metallic,
                                     double roughness) {
  ProductMaterial m;
  m.baseColour = glm::clamp(baseColour, 0.0, 1.0);
  m.metallic = std::clamp(metallic, 0.0, 1.0);
  m.roughness = std::clamp(roughness, 0.0, 1.0);
  m.diffuse = m.baseColour * (1 - m.metallic);
  m.specular = glm::dvec3(0.04 * (1 - m.metallic)) + m.baseColour * m.metallic;
  const double alpha = std::max(m.roughness * m.roughness, 1e-3);
  m.specularExponent = std::clamp(2 / (alpha * alpha) - 2, 1.0, 4096.0);
  return m;
}

}  // namespace penumbra::scene

#ifdef PENUMBRA_HAVE_GLTF

#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>

#include <cstring>
#include <string>
#include <system_error>

namespace penumbra::scene {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw MeshError(path.string() + ": " + what);
}

glm::dmat4 nodeTransform(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(c) * 4 + size_t(r)];  // column-major
    }
    return m;
  }
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (n.translation.size() == 3) {
    t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
  }
  if (n.rotation.size() == 4) {
    const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // w, x, y, z
    r = glm::dmat4(glm::mat3_cast(glm::normalize(q)));
  }
  if (n.scale.size() == 3) {
    s[0][0] = n.scale[0];
    s[1][1] = n.scale[1];
    s[2][2] = n.scale[2];
  }
  return t * r * s;
}

class Reader {
 public:
  Reader(const std::filesystem::path& path, const tinygltf::Model& model)
      : path_(path), m_(model) {}

  // Element `i` of accessor `a` as doubles (`components` of them).
  struct View {
    const unsigned char* data;
    size_t stride, count;
    int componentType, components;
  };

  View view(int accessorIndex, const std::string& what) const {
    if (accessorIndex < 0 || size_t(accessorIndex) >= m_.accessors.size()) {
      fail(path_, what + ": accessor " + std::to_string(accessorIndex) + " does not exist");
    }
    const tinygltf::Accessor& a = m_.accessors[size_t(accessorIndex)];
    if (a.sparse.isSparse) fail(path_, what + ": sparse accessors are not supported");
    if (a.bufferView < 0 || size_t(a.bufferView) >= m_.bufferViews.size()) {
      fail(path_, what + ": accessor without a valid bufferView");
    }
    const tinygltf::BufferView& bv = m_.bufferViews[size_t(a.bufferView)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m_.buffers.size()) {
      fail(path_, what + ": bufferView without a valid buffer");
    }
    const std::vector<unsigned char>& buf = m_.buffers[size_t(bv.buffer)].data;
    const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    if (components <= 0 || size <= 0) fail(path_, what + ": unknown accessor type");
    const size_t element = size_t(components) * size_t(size);
    const size_t stride = bv.byteStride ? bv.byteStride : element;
    if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset) {
      fail(path_, what + ": bufferView runs past the end of its buffer");
    }
    if (a.count > 0 &&
        (a.byteOffset > bv.byteLength || (a.count - 1) > (bv.byteLength - a.byteOffset) / stride ||
         a.byteOffset + (a.count - 1) * stride + element > bv.byteLength)) {
      fail(path_, what + ": accessor runs past the end of its bufferView");
    }
    return {buf.data() + bv.byteOffset + a.byteOffset, stride, a.count, a.componentType,
            components};
  }

  const std::filesystem::path& path_;
  const tinygltf::Model& m_;
};

template <class T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

}  // namespace

namespace {

// The files a glTF may read (itself, its buffers and images, through tinygltf's file
// callbacks): regular files of at most kMaxModelFileBytes inside the glTF's own folder. An
// image `uri` of "/" or ".." is a folder (tinygltf's own reader asked the allocator for
// 2^63 bytes for it), "/dev/zero" never ends, and "../../etc/passwd" is no part of the
// model; each is refused with the first such problem kept for the message, since tinygltf
// treats a missing image as a mere warning.
struct ModelFiles {
  std::filesystem::path folder;  // weakly canonical
  std::string refusal;           // the first refused file, empty when none

  bool accept(const std::string& file) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(file, ec);
    std::string problem;
    const std::filesystem::file_status st = std::filesystem::status(p, ec);
    const auto [end, _] = std::mismatch(folder.begin(), folder.end(), p.begin(), p.end());
    if (ec || !std::filesystem::exists(st)) {
      problem = "no such file";
    } else if (end != folder.end()) {
      problem = "is outside the model's folder " + folder.string();
    } else if (!std::filesystem::is_regular_file(st)) {
      problem = "is not a regular file";
    } else if (std::filesystem::file_size(p, ec) > kMaxModelFileBytes || ec) {
      problem = "is larger than " + std::to_string(kMaxModelFileBytes) + " bytes";
    }
    if (problem.empty()) return true;
    if (refusal.empty()) refusal = "\"" + file + "\" " + problem;
    return false;
  }

  static bool exists(const std::string& file, void* self) {
    return static_cast<ModelFiles*>(self)->accept(file);
  }
  // No `~` or environment expansion (tinygltf's default runs wordexp on the uri).
  static std::string expand(const std::string& file, void*) { return file; }
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& file,
                   void* self) {
    if (!static_cast<ModelFiles*>(self)->accept(file)) {
      if (err) *err += static_cast<ModelFiles*>(self)->refusal;
      return false;
    }
    try {
      const std::vector<uint8_t> bytes = core::readRegularFile(
          file, kMaxModelFileBytes, "a model file", core::throwAs<core::Error>);
      out->assign(bytes.begin(), bytes.end());
    } catch (const core::Error& e) {  // tinygltf reports through `err`, not exceptions
      if (err) *err += e.what();
      return false;
    }
    if (out->empty()) {  // tinygltf indexes the first byte unchecked
      if (err) *err += "\"" + file + "\": empty file";
      return false;
    }
    return true;
  }
  static bool write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
    return false;
  }
};

bool loadBoundedImage(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                      int reqWidth, int reqHeight, const unsigned char* bytes, int size,
                      void* user) {
  const auto wh = pngOrJpegSize(bytes, size_t(std::max(size, 0)));
  const std::string what = "images[" + std::to_string(index) + "]: ";
  if (!wh) {
    if (err) *err += what + "not a PNG or JPEG image";
    return false;
  }
  if (wh->first == 0 || wh->second == 0 || wh->first > kMaxTextureSide ||
      wh->second > kMaxTextureSide) {
    if (err) {
      *err += what + std::to_string(wh->first) + " x " + std::to_string(wh->second) +
              " pixels, expected 1 to " + std::to_string(kMaxTextureSide) + " per side";
    }
    return false;
  }
  return tinygltf::LoadImageData(image, index, err, warn, reqWidth, reqHeight, bytes, size, user);
}

tinygltf::Model readModel(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::error_code ec;
  ModelFiles files{std::filesystem::weakly_canonical(path, ec).parent_path(), {}};
  if (!files.accept(path.string())) fail(path, "cannot open file: " + files.refusal);
  loader.SetFsCallbacks(
      {&ModelFiles::exists, &ModelFiles::expand, &ModelFiles::read, &ModelFiles::write, &files});
  loader.SetImageLoader(&loadBoundedImage, nullptr);
  const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  if (!files.refusal.empty()) fail(path, "uri " + files.refusal);
  if (!ok) fail(path, "not a valid glTF 2.0 file: " + (err.empty() ? warn : err));
  return model;
}

// What a node's subtree adds to the flattened model, each instance counted: a node reused
// by several parents is instanced once per path from a root, so a DAG of n nodes can stand
// for 2^n instances. Counted with one memoized visit per node (saturating sums), before
// anything is flattened, so a hostile graph costs O(nodes + edges) to refuse.
struct SubtreeCost {
  size_t instances = 0, vertices = 0, triangles = 0;
};

constexpr size_t kMaxNodeInstances = 65536;  // a catalogue product has tens to hundreds
constexpr int kMaxNodeDepth = 64;

size_t saturatingAdd(size_t a, size_t b) {
  return a > std::numeric_limits<size_t>::max() - b ? std::numeric_limits<size_t>::max() : a + b;
}

class NodeGraphCost {
 public:
  NodeGraphCost(const std::filesystem::path& path, const tinygltf::Model& model)
      : path_(path),
        model_(model),
        state_(model.nodes.size(), kUnvisited),
        cost_(model.nodes.size()) {}

  SubtreeCost of(int n, int depth) {
    if (n < 0 || size_t(n) >= model_.nodes.size()) {
      fail(path_, "node " + std::to_string(n) + " does not exist");
    }
    if (depth > kMaxNodeDepth) {
      fail(path_, "node hierarchy deeper than " + std::to_string(kMaxNodeDepth));
    }
    uint8_t& state = state_[size_t(n)];
    if (state == kDone) return cost_[size_t(n)];
    if (state == kOnPath) {
      fail(path_, "nodes[" + std::to_string(n) + "]: the node is its own ancestor (a cycle)");
    }
    state = kOnPath;
    const tinygltf::Node& node = model_.nodes[size_t(n)];
    SubtreeCost c{1, 0, 0};
    if (node.mesh >= 0 && size_t(node.mesh) < model_.meshes.size()) {
      for (const tinygltf::Primitive& prim : model_.meshes[size_t(node.mesh)].primitives) {
        if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) continue;
        const auto pos = prim.attributes.find("POSITION");
        const size_t vertices = pos == prim.attributes.end() ? 0 : accessorCount(pos->second);
        c.vertices = saturatingAdd(c.vertices, vertices);
        c.triangles = saturatingAdd(
            c.triangles, (prim.indices >= 0 ? accessorCount(prim.indices) : vertices) / 3);
      }
    }
    for (int child : node.children) {
      const SubtreeCost k = of(child, depth + 1);
      c.instances = saturatingAdd(c.instances, k.instances);
      c.vertices = saturatingAdd(c.vertices, k.vertices);
      c.triangles = saturatingAdd(c.triangles, k.triangles);
    }
    state = kDone;
    return cost_[size_t(n)] = c;
  }

 private:
  enum : uint8_t { kUnvisited, kOnPath, kDone };
  size_t accessorCount(int a) const {
    return a >= 0 && size_t(a) < model_.accessors.size() ? model_.accessors[size_t(a)].count : 0;
  }
  const std::filesystem::path& path_;
  const tinygltf::Model& model_;
  std::vector<uint8_t> state_;
  std::vector<SubtreeCost> cost_;
};

// Refuses a node graph with a cycle, or whose flattened model would exceed the limits of
// mesh_io.h, before the walk that builds it.
void checkNodeGraph(const std::filesystem::path& path, const tinygltf::Model& model,
                    const std::vector<int>& roots) {
  NodeGraphCost graph(path, model);
  SubtreeCost total;
  for (int r : roots) {
    const SubtreeCost c = graph.of(r, 0);
    total.instances = saturatingAdd(total.instances, c.instances);
    total.vertices = saturatingAdd(total.vertices, c.vertices);
    total.triangles = saturatingAdd(total.triangles, c.triangles);
  }
  const auto over = [&](size_t n, size_t limit, const std::string& what) {
    if (n <= limit) return;
    fail(path,
         "nodes: the scene instances " +
             (n == std::numeric_limits<size_t>::max() ? "more than 2^64" : std::to_string(n)) +
             " " + what + ", more than the " + std::to_string(limit) + " a model may have");
  };
  over(total.instances, kMaxNodeInstances, "nodes");
  over(total.triangles, kMaxMeshTriangles, "triangles");
  over(total.vertices, kMaxMeshVertices, "vertices");
}

// The root nodes: the default scene's (the first scene's without one), or, in a file
// without scenes, every node that is no node's child.
std::vector<int> sceneRoots(const std::filesystem::path& path, const tinygltf::Model& model) {
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const size_t s = model.defaultScene >= 0 ? size_t(model.defaultScene) : 0;
    if (s >= model.scenes.size()) fail(path, "default scene does not exist");
    roots = model.scenes[s].nodes;
  } else {
    std::vector<uint8_t> isChild(model.nodes.size(), 0);
    for (const tinygltf::Node& n : model.nodes) {
      for (int c : n.children) {
        if (c >= 0 && size_t(c) < isChild.size()) isChild[size_t(c)] = 1;
      }
    }
    for (size_t i = 0; i < model.nodes.size(); ++i) {
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
  }
  return roots;
}

// Flattens the node hierarchy into one mesh in world space and averages the primitives'
// materials, each weighted by its triangle count (sums in visiting order).
class SceneFlattener {
 public:
  SceneFlattener(const std::filesystem::path& path, const tinygltf::Model& model)
      : path_(path), model_(model), reader_(path, model) {}

  void visit(int n, const glm::dmat4& parent, int depth) {
    const std::filesystem::path& path = path_;
    const tinygltf::Model& model = model_;
    if (n < 0 || size_t(n) >= model.nodes.size()) {
      fail(path, "node " + std::to_string(n) + " does not exist");
    }
    if (depth > kMaxNodeDepth) fail(path, "node hierarchy deeper than 64");
    const tinygltf::Node& node = model.nodes[size_t(n)];
    const glm::dmat4 world = parent * nodeTransform(node);
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= model.meshes.size()) {
        fail(path, "nodes[" + std::to_string(n) + "].mesh does not exist");
      }
      const tinygltf::Mesh& mesh = model.meshes[size_t(node.mesh)];
      for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        addPrimitive(
            mesh.primitives[p], world,
            "meshes[" + std::to_string(node.mesh) + "].primitives[" + std::to_string(p) + "]");
      }
    }
    for (int child : node.children) visit(child, world, depth + 1);
  }

  GltfModel finish() {
    if (out_.mesh.indices.empty()) fail(path_, "no triangles in the default scene");
    out_.material.diffuse = diffuseSum_ / weightSum_;
    out_.material.specular = specularSum_ / weightSum_;
    out_.material.baseColour = baseSum_ / weightSum_;
    out_.material.specularExponent = exponentSum_ / weightSum_;
    out_.material.metallic = metallicSum_ / weightSum_;
    out_.material.roughness = roughnessSum_ / weightSum_;
    return std::move(out_);
  }

 private:
  void addPrimitive(const tinygltf::Primitive& prim, const glm::dmat4& world,
                    const std::string& what) {
    const std::filesystem::path& path = path_;
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) return;
    const std::vector<glm::dvec3> positions = worldPositions(prim, world, what);
    const std::vector<uint32_t> idx = indices(prim, positions.size(), what);
    if (idx.size() % 3 != 0) fail(path, what + ": index count is not a multiple of 3");
    const bool mirrored = glm::determinant(glm::dmat3(world)) < 0;
    const std::vector<glm::dvec3> normals = worldNormals(prim, world, positions.size(), what);
    const std::vector<glm::dvec3> reflectances = vertexReflectances(prim, positions.size(), what);
    TriangleMesh& out = out_.mesh;
    const uint32_t base = static_cast<uint32_t>(out.positions.size());
    if (!normals.empty()) {
      // The file's normals: one vertex per glTF vertex.
      out.positions.insert(out.positions.end(), positions.begin(), positions.end());
      out.normals.insert(out.normals.end(), normals.begin(), normals.end());
      out.reflectances.insert(out.reflectances.end(), reflectances.begin(), reflectances.end());
      for (size_t t = 0; t < idx.size(); t += 3) {
        out.indices.push_back(base + idx[t]);
        out.indices.push_back(base + idx[t + (mirrored ? 2 : 1)]);
        out.indices.push_back(base + idx[t + (mirrored ? 1 : 2)]);
      }
    } else if (!idx.empty()) {
      // glTF 2.0 §3.7.2.1: "When normals are not specified, client implementations MUST
      // calculate flat normals": crease angle 0 (only coplanar neighbours share a vertex).
      PolygonSoup soup;
      soup.positions = positions;
      soup.reflectances = reflectances;
      for (size_t t = 0; t < idx.size(); t += 3) {
        for (const size_t k : {t, t + (mirrored ? 2 : 1), t + (mirrored ? 1 : 2)}) {
          soup.cornerPosition.push_back(idx[k]);
          soup.cornerAttribute.push_back(idx[k]);  // the glTF vertex: its colour
        }
        soup.endFace();
      }
      soup.cornerNormal.assign(soup.cornerPosition.size(), kNoAttribute);
      const TriangleMesh flat = buildTriangleMesh(soup, 0.0);
      out.positions.insert(out.positions.end(), flat.positions.begin(), flat.positions.end());
      out.normals.insert(out.normals.end(), flat.normals.begin(), flat.normals.end());
      out.reflectances.insert(out.reflectances.end(), flat.reflectances.begin(),
                              flat.reflectances.end());
      for (uint32_t i : flat.indices) out.indices.push_back(base + i);
    }
    const ProductMaterial pm = material(prim, what);
    const size_t triangles = idx.size() / 3;  // idx holds whole triangles
    const double w = double(triangles);
    diffuseSum_ += w * pm.diffuse;
    specularSum_ += w * pm.specular;
    baseSum_ += w * pm.baseColour;
    exponentSum_ += w * pm.specularExponent;
    metallicSum_ += w * pm.metallic;
    roughnessSum_ += w * pm.roughness;
    weightSum_ += w;
  }

  // Element i of a float accessor, or of a normalized unsigned byte or short one (glTF 2.0
  // §3.11: c / 255, c / 65535); w = 1 when it has three components.
  glm::dvec4 element(const Reader::View& v, size_t i) const {
    const unsigned char* p = v.data + i * v.stride;
    glm::dvec4 out(0.0, 0.0, 0.0, 1.0);
    for (int c = 0; c < v.components && c < 4; ++c) {
      switch (v.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          out[c] = load<float>(p + 4 * c);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          out[c] = p[c] / 255.0;
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
          out[c] = load<uint16_t>(p + 2 * c) / 65535.0;
          break;
        default:
          break;
      }
    }
    return out;
  }

  // An optional per-vertex attribute with `count` elements of `components` in {minC, maxC}
  // components: float, or normalized unsigned byte/short where `normalizedOk`.
  std::optional<Reader::View> attribute(const tinygltf::Primitive& prim, const std::string& name,
                                        size_t count, int minComponents, int maxComponents,
                                        bool normalizedOk, const std::string& what) const {
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) return std::nullopt;
    const std::string where = what + "." + name;
    const Reader::View v = reader_.view(it->second, where);
    const bool typeOk =
        v.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        (normalizedOk && (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
    if (!typeOk || v.components < minComponents || v.components > maxComponents) {
      fail(path_, where + ": unsupported accessor type");
    }
    if (v.count != count) {
      fail(path_, where + ": " + std::to_string(v.count) + " elements for " +
                      std::to_string(count) + " positions");
    }
    return v;
  }

  // NORMAL through the inverse transpose of the node's world matrix (normals are covectors:
  // this keeps them perpendicular under non-uniform scale and points them the right way
  // under a mirroring one), normalized. Empty when the primitive has none.
  std::vector<glm::dvec3> worldNormals(const tinygltf::Primitive& prim, const glm::dmat4& world,
                                       size_t count, const std::string& what) const {
    std::vector<glm::dvec3> normals;
    const auto v = attribute(prim, "NORMAL", count, 3, 3, false, what);
    if (!v) return normals;
    const glm::dmat3 m = glm::transpose(glm::inverse(glm::dmat3(world)));
    normals.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      const glm::dvec3 n = m * glm::dvec3(element(*v, i));
      const double length = glm::length(n);
      if (!(length > 0) || !std::isfinite(length)) {
        fail(path_, what + ".NORMAL: element " + std::to_string(i) +
                        " is zero or not finite (in the node's space)");
      }
      normals.push_back(n / length);
    }
    return normals;
  }

  // A primitive's glTF metallic-roughness material as read: white, metallic 1 and roughness
  // 1 without one (glTF's default material).
  struct BaseColour {
    glm::dvec3 factor{1.0};
    double metallic = 1, roughness = 1;
    const Texture* texture = nullptr;  // the decoded base-colour texture, if any
    TextureWrap wrapS = TextureWrap::kRepeat, wrapT = TextureWrap::kRepeat;
    int texCoord = 0;  // its TEXCOORD_n set
  };

  BaseColour baseColour(const tinygltf::Primitive& prim, const std::string& what) {
    BaseColour b;
    if (prim.material < 0) return b;
    if (size_t(prim.material) >= model_.materials.size()) {
      fail(path_, what + ": material " + std::to_string(prim.material) + " does not exist");
    }
    const tinygltf::PbrMetallicRoughness& pbr =
        model_.materials[size_t(prim.material)].pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() >= 3) {
      b.factor = glm::dvec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
    }
    b.metallic = pbr.metallicFactor;
    b.roughness = pbr.roughnessFactor;
    for (int ch = 0; ch < 3; ++ch) {
      if (!std::isfinite(b.factor[ch])) fail(path_, what + ": non-finite base colour");
    }
    if (!std::isfinite(b.metallic) || !std::isfinite(b.roughness)) {
      fail(path_, what + ": non-finite metallic/roughness");
    }
    const int tex = pbr.baseColorTexture.index;
    if (tex >= 0 && size_t(tex) < model_.textures.size()) {
      const tinygltf::Texture& t = model_.textures[size_t(tex)];
      b.texture = decodedImage(t.source, what);
      if (t.sampler >= 0 && size_t(t.sampler) < model_.samplers.size()) {
        b.wrapS = wrap(model_.samplers[size_t(t.sampler)].wrapS);
        b.wrapT = wrap(model_.samplers[size_t(t.sampler)].wrapT);
      }
      b.texCoord = pbr.baseColorTexture.texCoord;
    }
    return b;
  }

  static glm::dvec3 meanTexel(const Texture& t) {
    glm::dvec3 sum(0.0);
    for (const glm::dvec3& texel : t.texels) sum += texel;
    return sum / double(t.texels.size());
  }

  // Per vertex: the diffuse reflectance of base colour = baseColorFactor (*) the base-colour
  // texture at the vertex's uv (bilinear, linear RGB, the sampler's wrap modes) (*) COLOR_0,
  // mapped by mapMetallicRoughness.
  std::vector<glm::dvec3> vertexReflectances(const tinygltf::Primitive& prim, size_t count,
                                             const std::string& what) {
    BaseColour b = baseColour(prim, what);
    std::optional<Reader::View> uv;
    if (b.texture) {
      const std::string set = "TEXCOORD_" + std::to_string(b.texCoord);
      uv = attribute(prim, set, count, 2, 2, true, what);
      if (!uv) {
        // Nowhere to sample it: its mean colour, as before per-vertex colours.
        out_.mesh.warnings.push_back(path_.string() + ": " + what +
                                     ": base-colour texture without " + set +
                                     ": its mean colour is used");
        b.factor *= meanTexel(*b.texture);
        b.texture = nullptr;
      }
    }
    const auto colour0 = attribute(prim, "COLOR_0", count, 3, 4, true, what);
    std::vector<glm::dvec3> out(count);
    for (size_t i = 0; i < count; ++i) {
      glm::dvec3 c = b.factor;
      if (b.texture) {
        const glm::dvec4 t = element(*uv, i);
        if (!std::isfinite(t.x) || !std::isfinite(t.y)) {
          fail(path_, what + ".TEXCOORD: element " + std::to_string(i) + " is not finite");
        }
        c *= sampleBilinear(*b.texture, t.x, t.y, b.wrapS, b.wrapT);
      }
      if (colour0) c *= glm::dvec3(element(*colour0, i));  // COLOR_0 is linear already
      for (int ch = 0; ch < 3; ++ch) {
        if (!std::isfinite(c[ch])) fail(path_, what + ".COLOR_0: non-finite colour");
      }
      out[i] = mapMetallicRoughness(c, b.metallic, b.roughness).diffuse;
    }
    return out;
  }

  static TextureWrap wrap(int mode) {
    if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::kClampToEdge;
    if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::kMirroredRepeat;
    return TextureWrap::kRepeat;
  }

  // Image `source` in linear RGB, converted once; null (warned about once) when it has no
  // decoded pixels.
  const Texture* decodedImage(int source, const std::string& what) {
    if (source < 0 || size_t(source) >= model_.images.size()) return nullptr;
    if (const auto it = textures_.find(source); it != textures_.end()) {
      return it->second ? &*it->second : nullptr;
    }
    const tinygltf::Image& img = model_.images[size_t(source)];
    const size_t texels =
        img.width > 0 && img.height > 0 ? size_t(img.width) * size_t(img.height) : 0;
    const size_t bytesPer = img.bits == 16 ? 2 : 1;
    std::optional<Texture>& t = textures_[source];
    if (texels == 0 || (img.bits != 8 && img.bits != 16) || img.component < 1 ||
        img.component > 4 || img.image.size() != texels * size_t(img.component) * bytesPer) {
      out_.mesh.warnings.push_back(path_.string() + ": " + what + ": images[" +
                                   std::to_string(source) +
                                   "] has no decoded pixels: the base colour factor alone is used");
      return nullptr;
    }
    t = textureFromSamples(uint32_t(img.width), uint32_t(img.height), img.component, img.bits,
                           img.image.data());
    return &*t;
  }

  // The primitive's positions in world space.
  std::vector<glm::dvec3> worldPositions(const tinygltf::Primitive& prim, const glm::dmat4& world,
                                         const std::string& what) const {
    const std::filesystem::path& path = path_;
    std::vector<glm::dvec3> positions;
    const auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) fail(path, what + ": no POSITION attribute");
    const Reader::View v = reader_.view(pos->second, what + ".POSITION");
    if (v.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || v.components != 3) {
      fail(path, what + ".POSITION: expected float VEC3");
    }
    for (size_t i = 0; i < v.count; ++i) {
      const unsigned char* p = v.data + i * v.stride;
      const glm::dvec4 q =
          world * glm::dvec4(load<float>(p), load<float>(p + 4), load<float>(p + 8), 1.0);
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
        fail(path, what + ".POSITION: non-finite position");
      }
      if (std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}) > kMaxModelCoordinate) {
        fail(path, what + ".POSITION: position outside [-1e6, 1e6] (model units)");
      }
      positions.emplace_back(q.x, q.y, q.z);
    }
    return positions;
  }

  // The primitive's triangle corners, relative to its first vertex: its index accessor,
  // or 0, 1, 2, ... without one.
  std::vector<uint32_t> indices(const tinygltf::Primitive& prim, size_t vertexCount,
                                const std::string& what) const {
    const std::filesystem::path& path = path_;
    std::vector<uint32_t> idx;
    if (prim.indices >= 0) {
      const Reader::View iv = reader_.view(prim.indices, what + ".indices");
      if (iv.components != 1) fail(path, what + ".indices: expected SCALAR");
      for (size_t i = 0; i < iv.count; ++i) {
        const unsigned char* p = iv.data + i * iv.stride;
        uint32_t k = 0;
        switch (iv.componentType) {
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            k = *p;
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            k = load<uint16_t>(p);
            break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            k = load<uint32_t>(p);
            break;
          default:
            fail(path, what + ".indices: expected an unsigned integer type");
        }
        if (k >= vertexCount) fail(path, what + ".indices: index out of range");
        idx.push_back(k);
      }
    } else {
      for (size_t i = 0; i < vertexCount; ++i) idx.push_back(static_cast<uint32_t>(i));
    }
    return idx;
  }

  // The primitive's material (glTF metallic-roughness, base colour times the mean of its
  // texture), mapped to Penumbra's; white, metallic 1 and roughness 1 without one.
  ProductMaterial material(const tinygltf::Primitive& prim, const std::string& what) {
    const BaseColour b = baseColour(prim, what);
    return mapMetallicRoughness(b.texture ? b.factor * meanTexel(*b.texture) : b.factor, b.metallic,
                                b.roughness);
  }

  const std::filesystem::path& path_;
  const tinygltf::Model& model_;
  const Reader reader_;
  GltfModel out_;
  std::map<int, std::optional<Texture>> textures_;  // base-colour images by index
  glm::dvec3 diffuseSum_{0.0}, specularSum_{0.0}, baseSum_{0.0};
  double exponentSum_ = 0, metallicSum_ = 0, roughnessSum_ = 0, weightSum_ = 0;
};

}  // namespace

GltfModel loadGltf(const std::filesystem::path& path) {
  const tinygltf::Model model = readModel(path);
  SceneFlattener scene(path, model);
  const std::vector<int> roots = sceneRoots(path, model);
  checkNodeGraph(path, model, roots);
  for (int r : roots) scene.visit(r, glm::dmat4(1.0), 0);
  return scene.finish();
}

}  // namespace penumbra::scene

#endif  // PENUMBRA_HAVE_GLTF
