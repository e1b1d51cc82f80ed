#include "scene/gltf_io.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

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
  ASSERT_EQ(g.mesh.positions.size(), ply.positions.size());
  ASSERT_EQ(g.mesh.indices, ply.indices);
  for (size_t i = 0; i < ply.positions.size(); ++i) {
    // Parent scale 0.016 of the child's translation by (1, 0, 0).
    const glm::dvec3 want = 0.016 * (ply.positions[i] + glm::dvec3(1, 0, 0));
    ASSERT_NEAR(glm::length(g.mesh.positions[i] - want), 0.0, 1e-12) << i;
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
  EXPECT_EQ(loadMesh(dir / "teapot.gltf").indices, ply.indices);
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
