#include "scene/gltf_io.h"

#include <gtest/gtest.h>

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
              "deeper than 64");
  expectError("lines.gltf", replaced("\"mode\": 4", "\"mode\": 1"), "no triangles");
  try {
    loadGltf(dir_ / "missing.gltf");
    ADD_FAILURE();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.gltf"), std::string::npos);
  }
}
#endif

}  // namespace
}  // namespace penumbra::scene
