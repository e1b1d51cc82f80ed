#include "scene/gltf_io.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "scene/image_io.h"
#include "tests/test_data.h"

namespace penumbra::scene {
namespace {

TEST(GltfMaterial, MetallicRoughnessMapping) {
  const ProductMaterial dielectric = mapMetallicRoughness(glm::dvec3(0.8, 0.5, 0.2), 0.0, 0.5);
  EXPECT_EQ(dielectric.diffuse, glm::dvec3(0.8, 0.5, 0.2));
  EXPECT_EQ(dielectric.specular, glm::dvec3(0.04));
  EXPECT_NEAR(dielectric.specularExponent, 2 / (0.25 * 0.25) - 2, 1e-9);  // alpha = r^2
  const ProductMaterial metal = mapMetallicRoughness(glm::dvec3(0.9, 0.6, 0.3), 1.0, 1.0);
  EXPECT_EQ(metal.diffuse, glm::dvec3(0.0));
  EXPECT_EQ(metal.specular, glm::dvec3(0.9, 0.6, 0.3));
  EXPECT_EQ(metal.specularExponent, 1.0);  // broadest lobe
  const ProductMaterial mirror = mapMetallicRoughness(glm::dvec3(2.0, -1.0, 0.5), 3.0, 0.0);
  EXPECT_EQ(mirror.baseColour, glm::dvec3(1.0, 0.0, 0.5));  // clamped
  EXPECT_EQ(mirror.specularExponent, 4096.0);
}

#ifdef PENUMBRA_HAVE_GLTF
namespace fs = std::filesystem;

double srgb(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

TEST(GltfIo, TeapotMatchesThePlyThroughTheNodeTransforms) {
  const fs::path dir = testing::dataDir() / "models";
  const GltfModel g = loadGltf(dir / "teapot.gltf");
  const TriangleMesh ply = loadMesh(dir / "teapot.ply");
  // The glTF has no NORMAL: flat normals (glTF 2.0 §3.7.2.1), so its vertices split
  // differently from the PLY's crease-angle ones; the triangles' corners are the same.
  ASSERT_EQ(g.mesh.indices.size(), ply.indices.size());
  for (size_t i = 0; i < ply.indices.size(); ++i) {
    // Parent scale 0.016 of the child's translation by (1, 0, 0).
    const glm::dvec3 want = 0.016 * (ply.positions[ply.indices[i]] + glm::dvec3(1, 0, 0));
    ASSERT_NEAR(glm::length(g.mesh.positions[g.mesh.indices[i]] - want), 0.0, 1e-12) << i;
  }
  for (size_t t = 0; t < g.mesh.triangleCount(); ++t) {
    const glm::dvec3 &a = g.mesh.positions[g.mesh.indices[3 * t]],
                     &b = g.mesh.positions[g.mesh.indices[3 * t + 1]],
                     &c = g.mesh.positions[g.mesh.indices[3 * t + 2]];
    const glm::dvec3 face = glm::normalize(glm::cross(b - a, c - a));
    ASSERT_GT(glm::dot(g.mesh.normals[g.mesh.indices[3 * t]], face), 1 - 1e-9) << t;
  }
  // Base colour (0.30, 0.42, 0.62) x the texture mean (two white texels, two sRGB 188).
  const double mean = (2 * 1.0 + 2 * srgb(188 / 255.0)) / 4;
  const glm::dvec3 c = glm::dvec3(0.30, 0.42, 0.62) * mean;
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_NEAR(g.material.baseColour[ch], c[ch], 1e-9);
    EXPECT_NEAR(g.material.diffuse[ch], c[ch], 1e-9);  // metallic 0
  }
  EXPECT_NEAR(g.material.specular.x, 0.04, 1e-12);
  EXPECT_NEAR(g.material.roughness, 0.35, 1e-12);
  EXPECT_NEAR(g.material.specularExponent, mapMetallicRoughness(c, 0, 0.35).specularExponent, 1e-9);
  // loadMesh() dispatches on the extension.
  EXPECT_EQ(loadMesh(dir / "teapot.gltf").indices, g.mesh.indices);
}

// Base64 (RFC 4648) for the data: URIs of the fixtures written below.
std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* const k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = uint32_t(bytes[i]) << 16 |
                       (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? uint32_t(bytes[i + 2]) : 0);
    out += k[n >> 18 & 63];
    out += k[n >> 12 & 63];
    out += i + 1 < bytes.size() ? k[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? k[n & 63] : '=';
  }
  return out;
}

template <class T>
void append(std::vector<uint8_t>& out, std::initializer_list<T> values) {
  for (T v : values) {
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
  }
}

// Issue 15 item 6: "a textured glTF is reduced to one average colour". A quad with NORMAL,
// TEXCOORD_0 and COLOR_0 under a node scaled (2, 1, -1) (non-uniform and mirroring), its
// base colour a 2 x 2 texture (red, green / blue, white; clamped) times (0.5, 1, 1).
TEST(GltfIo, NormalsTexturesAndVertexColoursPerVertex) {
  const fs::path dir =
      fs::temp_directory_path() / ("penumbra_gltf_vc_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::vector<uint8_t> rgba = {255, 0, 0,   255, 0,   255, 0,   255,
                                     0,   0, 255, 255, 255, 255, 255, 255};
  try {
    writePng(dir / "tex.png", 2, 2, rgba);
  } catch (const ImageError&) {
    fs::remove_all(dir);
    GTEST_SKIP() << "no PNG writer in this build";
  }
  std::vector<uint8_t> buf;
  append<float>(buf, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});  // POSITION
  const float r = 0.70710678f;
  append<float>(buf, {r, r, 0, r, r, 0, r, r, 0, r, r, 0});              // NORMAL
  append<float>(buf, {0, 0, 1, 0, 1, 1, 0, 1});                          // TEXCOORD_0
  append<float>(buf, {1, 1, 0.5f, 1, 1, 0.5f, 1, 1, 0.5f, 1, 1, 0.5f});  // COLOR_0
  append<uint16_t>(buf, {0, 1, 2, 0, 2, 3});                             // indices
  const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "scale": [2, 1, -1]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2,
      "COLOR_0": 3}, "indices": 4, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 1, 1, 1],
      "metallicFactor": 0, "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0, "sampler": 0}], "samplers": [{"wrapS": 33071, "wrapT": 33071}],
    "images": [{"uri": "tex.png"}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3"},
      {"bufferView": 0, "byteOffset": 96, "componentType": 5126, "count": 4, "type": "VEC2"},
      {"bufferView": 0, "byteOffset": 128, "componentType": 5126, "count": 4, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 176},
                    {"buffer": 0, "byteOffset": 176, "byteLength": 12}],
    "buffers": [{"byteLength": 188, "uri": "data:application/octet-stream;base64,)" +
                           base64(buf) + R"("}]})";
  ASSERT_EQ(buf.size(), 188u);
  std::ofstream(dir / "quad.gltf") << gltf;
  const GltfModel g = loadGltf(dir / "quad.gltf");
  fs::remove_all(dir);
  ASSERT_EQ(g.mesh.positions.size(), 4u);
  ASSERT_EQ(g.mesh.reflectances.size(), 4u);
  EXPECT_TRUE(g.mesh.warnings.empty());
  // uv (0, 0) reads the top-left texel, (1, 0) top-right, (1, 1) bottom-right, (0, 1)
  // bottom-left; times the factor and COLOR_0.
  EXPECT_EQ(g.mesh.reflectances[0], glm::dvec3(0.5, 0, 0));
  EXPECT_EQ(g.mesh.reflectances[1], glm::dvec3(0, 1, 0));
  EXPECT_EQ(g.mesh.reflectances[2], glm::dvec3(0.5, 1, 0.5));
  EXPECT_EQ(g.mesh.reflectances[3], glm::dvec3(0, 0, 0.5));
  // Normals through the inverse transpose diag(1/2, 1, -1): (r, r, 0) -> (r/2, r, 0).
  const glm::dvec3 want = glm::normalize(glm::dvec3(0.5, 1, 0));
  for (const glm::dvec3& n : g.mesh.normals) EXPECT_NEAR(glm::length(n - want), 0.0, 1e-7);
  // The mirror z -> -z turns the quad's front (+z in the file) to -z: the winding was
  // reversed so the geometric normal follows.
  const glm::dvec3 &a = g.mesh.positions[g.mesh.indices[0]],
                   &b = g.mesh.positions[g.mesh.indices[1]],
                   &c = g.mesh.positions[g.mesh.indices[2]];
  EXPECT_LT(glm::cross(b - a, c - a).z, 0.0);
}

class GltfCorrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("penumbra_gltf_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ifstream in(testing::dataDir() / "models" / "teapot.gltf");
    good_.assign(std::istreambuf_iterator<char>(in), {});
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` as NAME and expects MeshError naming the file and containing `what`.
  void expectError(const std::string& name, const std::string& text, const std::string& what) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    try {
      loadGltf(p);
      ADD_FAILURE() << name << " loaded";
    } catch (const MeshError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(name), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  }
  std::string replaced(const std::string& from, const std::string& to) const {
    std::string s = good_;
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  }

  fs::path dir_;
  std::string good_;
};

TEST_F(GltfCorrupt, MalformedFilesGiveClearErrors) {
  expectError("garbage.gltf", "{ this is not json", "not a valid glTF");
  expectError("empty.glb", "", "not a valid glTF");
  expectError("truncated.glb", std::string("glTF\x02\0\0\0\xff\0\0\0", 12), "not a valid glTF");
  expectError("half.gltf", good_.substr(0, good_.size() / 2), "not a valid glTF");
  expectError("count.gltf", replaced("\"count\": 792", "\"count\": 100000"), "POSITION");
  expectError("index.gltf", replaced("\"count\": 792", "\"count\": 10"), "index out of range");
  expectError("type.gltf", replaced("\"componentType\": 5126", "\"componentType\": 5121"),
              "expected float VEC3");
  expectError("nomesh.gltf", replaced("\"mesh\": 0", "\"mesh\": 4"), "does not exist");
  expectError("cycle.gltf", replaced("\"mesh\": 0,", "\"mesh\": 0, \"children\": [0],"),
              "nodes[0]: the node is its own ancestor (a cycle)");
  expectError("lines.gltf", replaced("\"mode\": 4", "\"mode\": 1"), "no triangles");
  try {
    loadGltf(dir_ / "missing.gltf");
    ADD_FAILURE();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.gltf"), std::string::npos);
  }
}

// Issue 18: a node graph reusing its children stands for exponentially many instances. 40
// levels of a node whose two children are the same node make 2^40 teapots: refused from the
// memoized counts at once, instead of being flattened until memory runs out.
TEST_F(GltfCorrupt, NodeGraphReusingChildrenIsCountedNotWalked) {
  // Node 0 is the root, node 1 the teapot, nodes 2..41 the levels.
  std::string nodes =
      "\"nodes\": [{\"scale\": [0.016, 0.016, 0.016], \"children\": [2]}, "
      "{\"mesh\": 0}";
  for (int level = 2; level < 42; ++level) {
    const std::string child = level == 41 ? "1" : std::to_string(level + 1);
    nodes += ", {\"children\": [" + child + ", " + child + "]}";
  }
  std::string text = good_;
  const size_t from = text.find("\"nodes\": [\n  {\n   \"name\": \"metres\"");
  const size_t to = text.find("\"meshes\"");
  ASSERT_NE(from, std::string::npos);
  text.replace(from, to - from, nodes + "],\n ");
  const auto start = std::chrono::steady_clock::now();
  expectError("dag.gltf", text, "nodes: the scene instances ");
  expectError("dag.gltf", text, " nodes, more than the 65536 a model may have");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

// Issue 18: an image uri that is a folder ("/", ".."), a device or a file outside the
// model's folder is refused by name; tinygltf's own reader asked for 2^63 bytes.
TEST_F(GltfCorrupt, ImageUriMustBeARegularFileBesideTheModel) {
  const std::string png = "\"uri\": \"data:image/png;base64,";
  const std::string image =
      good_.substr(good_.find(png), good_.find("\"", good_.find(png) + 8) - good_.find(png) + 1);
  expectError("root.gltf", replaced(image, "\"uri\": \"/\""), "uri \"");
  // tinygltf joins every uri onto the model's folder: "/" names the folder itself.
  expectError("root.gltf", replaced(image, "\"uri\": \"/\""), "is not a regular file");
  expectError("up.gltf", replaced(image, "\"uri\": \"..\""), "is outside the model's folder");
  expectError("zero.gltf", replaced(image, "\"uri\": \"/dev/zero\""), "no such file");
  fs::create_symlink("/dev/zero", dir_ / "zero.png");
  expectError("link.gltf", replaced(image, "\"uri\": \"zero.png\""),
              "is outside the model's folder");
  fs::create_directories(dir_ / "textures");
  expectError("folder.gltf", replaced(image, "\"uri\": \"textures\""), "is not a regular file");
  expectError("absent.gltf", replaced(image, "\"uri\": \"absent.png\""), "no such file");
  std::ofstream(dir_ / "fake.png") << "not an image";
  expectError("fake.gltf", replaced(image, "\"uri\": \"fake.png\""),
              "images[0]: not a PNG or JPEG image");
  // A valid PNG header announcing 65535 x 65535 pixels: refused before it is decoded.
  std::string bomb("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\xff\xff\0\0\xff\xff\x08\x02\0\0\0", 29);
  std::ofstream(dir_ / "bomb.png", std::ios::binary) << bomb;
  expectError("bomb.gltf", replaced(image, "\"uri\": \"bomb.png\""),
              "images[0]: 65535 x 65535 pixels, expected 1 to 8192 per side");
}

// Positions are bounded in model units (mesh_io.h), after the node transforms.
TEST_F(GltfCorrupt, PositionsOutsideTheCoordinateRangeAreRefused) {
  expectError("huge.gltf", replaced("0.016,\n    0.016,\n    0.016", "1e12,\n    1e12,\n    1e12"),
              "POSITION: position outside [-1e6, 1e6]");
}
#endif

}  // namespace
}  // namespace penumbra::scene
