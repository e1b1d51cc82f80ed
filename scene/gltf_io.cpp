#include "scene/gltf_io.h"

#include <algorithm>
#include <cmath>

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

namespace penumbra::scene {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw MeshError(path.string() + ": " + what);
}

double srgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

glm::dmat4 nodeTransform(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(c * 4 + r)];  // column-major
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

tinygltf::Model readModel(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!std::filesystem::exists(path)) fail(path, "cannot open file");
  const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  if (!ok) fail(path, "not a valid glTF 2.0 file: " + (err.empty() ? warn : err));
  return model;
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
    if (depth > 64) fail(path, "node hierarchy deeper than 64 (a cycle?)");
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
    const uint32_t base = static_cast<uint32_t>(out_.mesh.positions.size());
    const size_t vertexCount = appendPositions(prim, world, what);
    const std::vector<uint32_t> idx = indices(prim, vertexCount, what);
    if (idx.size() % 3 != 0) fail(path, what + ": index count is not a multiple of 3");
    const bool mirrored = glm::determinant(glm::dmat3(world)) < 0;
    for (size_t t = 0; t < idx.size(); t += 3) {
      out_.mesh.indices.push_back(base + idx[t]);
      out_.mesh.indices.push_back(base + idx[t + (mirrored ? 2 : 1)]);
      out_.mesh.indices.push_back(base + idx[t + (mirrored ? 1 : 2)]);
    }
    const ProductMaterial pm = material(prim, what);
    const double w = double(idx.size() / 3);
    diffuseSum_ += w * pm.diffuse;
    specularSum_ += w * pm.specular;
    baseSum_ += w * pm.baseColour;
    exponentSum_ += w * pm.specularExponent;
    metallicSum_ += w * pm.metallic;
    roughnessSum_ += w * pm.roughness;
    weightSum_ += w;
  }

  // The primitive's positions in world space, appended to the mesh; returns their count.
  size_t appendPositions(const tinygltf::Primitive& prim, const glm::dmat4& world,
                         const std::string& what) {
    const std::filesystem::path& path = path_;
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
      out_.mesh.positions.emplace_back(q.x, q.y, q.z);
    }
    return v.count;
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
  ProductMaterial material(const tinygltf::Primitive& prim, const std::string& what) const {
    const std::filesystem::path& path = path_;
    const tinygltf::Model& model = model_;
    glm::dvec3 c(1.0);
    double metallic = 1, roughness = 1;
    if (prim.material >= 0) {
      if (size_t(prim.material) >= model.materials.size()) {
        fail(path, what + ": material " + std::to_string(prim.material) + " does not exist");
      }
      const tinygltf::PbrMetallicRoughness& pbr =
          model.materials[size_t(prim.material)].pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() >= 3) {
        c = glm::dvec3(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
      }
      metallic = pbr.metallicFactor;
      roughness = pbr.roughnessFactor;
      const int tex = pbr.baseColorTexture.index;
      if (tex >= 0 && size_t(tex) < model.textures.size()) {
        const int src = model.textures[size_t(tex)].source;
        if (src >= 0 && size_t(src) < model.images.size()) {
          const tinygltf::Image& img = model.images[size_t(src)];
          const size_t texels =
              img.width > 0 && img.height > 0 ? size_t(img.width) * size_t(img.height) : 0;
          if (texels > 0 && img.bits == 8 && img.component >= 3 &&
              img.image.size() == texels * size_t(img.component)) {
            glm::dvec3 mean(0.0);
            for (size_t i = 0; i < texels; ++i) {
              for (int ch = 0; ch < 3; ++ch) {
                mean[ch] += srgbToLinear(img.image[i * size_t(img.component) + size_t(ch)] / 255.0);
              }
            }
            c *= mean / double(texels);
          }
        }
      }
    }
    for (int ch = 0; ch < 3; ++ch) {
      if (!std::isfinite(c[ch])) fail(path, what + ": non-finite base colour");
    }
    if (!std::isfinite(metallic) || !std::isfinite(roughness)) {
      fail(path, what + ": non-finite metallic/roughness");
    }
    return mapMetallicRoughness(c, metallic, roughness);
  }

  const std::filesystem::path& path_;
  const tinygltf::Model& model_;
  const Reader reader_;
  GltfModel out_;
  glm::dvec3 diffuseSum_{0.0}, specularSum_{0.0}, baseSum_{0.0};
  double exponentSum_ = 0, metallicSum_ = 0, roughnessSum_ = 0, weightSum_ = 0;
};

}  // namespace

GltfModel loadGltf(const std::filesystem::path& path) {
  const tinygltf::Model model = readModel(path);
  SceneFlattener scene(path, model);
  for (int r : sceneRoots(path, model)) scene.visit(r, glm::dmat4(1.0), 0);
  return scene.finish();
}

}  // namespace penumbra::scene

#endif  // PENUMBRA_HAVE_GLTF
