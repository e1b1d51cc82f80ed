// Product model files (kiosk/product_files.h) with the faulty models of
// data/sessions/faulty-models/: each refused naming the file and the reason.
#include "kiosk/product_files.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "kiosk/kiosk_loop.h"
#include "tests/scratch_dir.h"

namespace penumbra::kiosk {
namespace {

namespace fs = std::filesystem;
const fs::path kData(PENUMBRA_DATA_DIR);

shadow::ProductModel current() {
  shadow::ProductModel p;
  p.name = "bunny";
  p.reflectance = glm::vec3(0.3f, 0.4f, 0.5f);
  p.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  p.mesh.indices = {0, 1, 2};
  p.proxy = p.mesh;
  return p;
}

std::string refusal(const fs::path& file) {
  try {
    loadProductFile(file, current());
  } catch (const ProductFileError& e) {
    return e.what();
  }
  return "accepted";
}

// A bundle's products are checked before the kiosk shows them: a fine proxy that is not
// usable, or too large to draw 16 times a frame, refuses its product with one line.
TEST(ProductFiles, ABundleProductWithABadFineProxyIsRefused) {
  shadow::SceneBundle bundle;
  bundle.products = {current(), current(), current()};
  bundle.products[1].name = "lamp";
  bundle.products[1].fineProxy = bundle.products[1].mesh;
  bundle.products[1].fineProxy.indices = {0, 1, 7};
  bundle.products[2].name = "sofa";
  for (uint32_t t = 0; t < 10001; ++t) {
    for (uint32_t c = 0; c < 3; ++c) bundle.products[2].fineProxy.indices.push_back(c);
  }
  bundle.products[2].fineProxy.positions = bundle.products[2].mesh.positions;
  std::vector<std::string> why;
  EXPECT_EQ(validateProducts(bundle, why), (std::vector<uint32_t>{0}));
  ASSERT_EQ(why.size(), 2u);
  EXPECT_EQ(why[0], "product lamp: fine shadow proxy index 7 past 3 vertices");
  EXPECT_EQ(why[1], "product sofa: fine shadow proxy has 10001 triangles (at most 10000)");
}

TEST(ProductFiles, FaultyModelsAreRefusedNamingFileAndReason) {
  const fs::path dir = kData / "sessions" / "faulty-models";
  const std::string truncatedObj = refusal(dir / "truncated.obj");
  EXPECT_EQ(truncatedObj.rfind((dir / "truncated.obj").string() + ":", 0), 0u) << truncatedObj;
  EXPECT_NE(truncatedObj.find("line"), std::string::npos) << truncatedObj;
  const std::string nan = refusal(dir / "nan-vertex.obj");
  EXPECT_EQ(nan.rfind((dir / "nan-vertex.obj").string() + ":", 0), 0u) << nan;
  EXPECT_NE(nan.find("non-finite"), std::string::npos) << nan;
  const std::string glb = refusal(dir / "truncated.glb");
  EXPECT_EQ(glb.rfind((dir / "truncated.glb").string() + ":", 0), 0u) << glb;
  EXPECT_NE(refusal(dir / "absent.obj").find("absent.obj"), std::string::npos);
}

TEST(ProductFiles, TooManyTrianglesForTheBoardIsRefused) {
  const fs::path file = test::scratchPath("product-files") / "dense.obj";
  fs::create_directories(file.parent_path());
  {
    std::ofstream o(file);
    o << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (size_t i = 0; i <= kMaxProductFileTriangles; ++i) o << "f 1 2 3\n";
  }
  EXPECT_NE(refusal(file).find("5001 triangles; at most 5000"), std::string::npos) << refusal(file);
  fs::remove_all(file.parent_path());
}

TEST(ProductFiles, GoodModelIsPlacedOnTheFloorAndKeepsTheMaterial) {
  const shadow::ProductModel m = loadProductFile(kData / "models" / "chair.obj", current());
  EXPECT_EQ(m.name, "bunny");
  EXPECT_EQ(m.reflectance, current().reflectance);
  EXPECT_GT(m.mesh.triangleCount(), 10u);
  EXPECT_EQ(m.proxy, m.mesh);
  float minY = 1e9f, minX = 1e9f, maxX = -1e9f;
  for (const core::Vec3& p : m.mesh.positions) {
    minY = std::min(minY, p.y), minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
  }
  EXPECT_EQ(minY, 0.0f);
  EXPECT_NEAR(minX + maxX, 0.0f, 1e-6f);
}

// Issue 15 item 6 on the board: a hot-swapped model brings its normals (a flat box: 24
// vertices, one normal per face) and its colours; an implausible size (a file in
// millimetres: product files are read in metres) is logged as a warning naming the file, and
// the model is still shown.
TEST(ProductFiles, SwappedModelsBringTheirNormalsColoursAndASizeWarning) {
  const fs::path dir = test::scratchPath("product-files-attributes");
  fs::create_directories(dir);
  const std::string box =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
  std::ofstream(dir / "box.mtl") << "newmtl oak\nKd 0.6 0.4 0.2\n";
  std::ofstream(dir / "box.obj") << "mtllib box.mtl\nusemtl oak\n" << box;
  std::vector<std::string> warnings;
  const shadow::ProductModel m = loadProductFile(dir / "box.obj", current(), &warnings);
  EXPECT_EQ(m.mesh.positions.size(), 24u);
  ASSERT_EQ(m.normals.size(), 24u);
  for (const glm::vec3& n : m.normals)
    EXPECT_EQ(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f);
  EXPECT_EQ(m.reflectances, std::vector<glm::vec3>(24, glm::vec3(0.6f, 0.4f, 0.2f)));
  EXPECT_TRUE(warnings.empty());  // a 1 m box

  // A 3 cm box (a model in metres meant to be scaled up, or a unit slip): too small.
  std::ofstream(dir / "small.obj")
      << "v 0 0 0\nv 0.03 0 0\nv 0.03 0.03 0\nv 0 0.03 0\nv 0 0 0.03\nv 0.03 0 0.03\n"
         "v 0.03 0.03 0.03\nv 0 0.03 0.03\n"
      << box.substr(box.find("f "));
  shadow::SceneBundle b;
  b.products = {current()};
  KioskLog log;
  EXPECT_EQ(swapProductFile(b, {"bunny", dir / "small.obj"}, log, 5), "");
  EXPECT_TRUE(b.products[0].reflectances.empty());  // no colours: the material's one
  EXPECT_EQ(b.products[0].normals.size(), 24u);
  EXPECT_TRUE(log.contains("product bunny: " + (dir / "small.obj").string() + ": measures 0.03 m"));
  fs::remove_all(dir);
}

TEST(ProductFiles, SwapKeepsTheLastGoodModelAndLogsWhy) {
  shadow::SceneBundle b;
  b.products = {current()};
  KioskLog log;
  const fs::path bad = kData / "sessions" / "faulty-models" / "nan-vertex.obj";
  const std::string why = swapProductFile(b, {"bunny", bad}, log, 7);
  EXPECT_NE(why.find("non-finite"), std::string::npos) << why;
  EXPECT_EQ(b.products[0].mesh, current().mesh) << "the last good model must stay";
  EXPECT_TRUE(log.contains("product bunny: refused " + bad.string()));
  EXPECT_EQ(swapProductFile(b, {"bunny", kData / "models" / "chair.obj"}, log, 8), "");
  EXPECT_NE(b.products[0].mesh, current().mesh);
  EXPECT_TRUE(log.contains("product bunny: model "));
  EXPECT_THROW(swapProductFile(b, {"sofa", bad}, log, 9), ProductFileError);
}

TEST(ProductFiles, WatcherAppliesNewAndChangedFilesOnly) {
  const fs::path dir = test::scratchPath("product-watch");
  fs::create_directories(dir);
  const fs::path file = dir / "bunny.obj";
  fs::copy_file(kData / "models" / "chair.obj", file);
  shadow::SceneBundle b;
  b.products = {current()};
  KioskLog log;
  ProductFileWatcher watcher({{"bunny", file}});
  auto changes = watcher.poll(b, log, 1);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_TRUE(changes[0].replaced);
  const core::Mesh chair = b.products[0].mesh;
  EXPECT_TRUE(watcher.poll(b, log, 2).empty()) << "an unchanged file is not read again";
  // A corrupt copy lands over it: refused, the chair stays.
  fs::copy_file(kData / "sessions" / "faulty-models" / "nan-vertex.obj", file,
                fs::copy_options::overwrite_existing);
  fs::last_write_time(file, fs::last_write_time(file) + std::chrono::seconds(1));
  changes = watcher.poll(b, log, 3);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_FALSE(changes[0].replaced);
  EXPECT_NE(changes[0].refusal.find("non-finite"), std::string::npos) << changes[0].refusal;
  EXPECT_EQ(b.products[0].mesh, chair);
  // Deleted: said once, then quiet until it is back.
  fs::remove(file);
  EXPECT_EQ(watcher.poll(b, log, 4).size(), 1u);
  EXPECT_TRUE(watcher.poll(b, log, 5).empty());
  EXPECT_EQ(b.products[0].mesh, chair);
  EXPECT_EQ(productFileFault("bunny"), "MODEL REFUSED: bunny");
  fs::remove_all(dir);
}

// Issue 18: a hot-swapped file is loaded off the frame loop. poll(kNo) starts the load and
// returns; until collect() applies it the bundle keeps the old model (only poll and collect
// touch it, on the caller's thread).
TEST(ProductFiles, LoadsInTheBackgroundAndKeepsTheOldModelMeanwhile) {
  const fs::path dir = test::scratchPath("product-background");
  fs::create_directories(dir);
  const fs::path file = dir / "bunny.obj";
  fs::copy_file(kData / "models" / "chair.obj", file, fs::copy_options::overwrite_existing);
  shadow::SceneBundle b;
  b.products = {current()};
  KioskLog log;
  ProductFileWatcher watcher({{"bunny", file}});
  auto changes = watcher.poll(b, log, 1, ProductFileWatcher::Wait::kNo);
  if (changes.empty()) {  // the load is still running: the old model is on screen
    EXPECT_TRUE(watcher.loading());
    EXPECT_EQ(b.products[0].mesh, current().mesh);
    changes = watcher.collect(b, log, 2, ProductFileWatcher::Wait::kUntilLoaded);
  }
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_TRUE(changes[0].replaced);
  EXPECT_FALSE(watcher.loading());
  EXPECT_NE(b.products[0].mesh, current().mesh);
  EXPECT_TRUE(watcher.collect(b, log, 3).empty());
  fs::remove_all(dir);
}

// Issue 18: the 230-byte binary PLY announcing 10^12 records of an element without
// properties hung the kiosk's main loop. Its load ends at once with a refusal: one log
// line, the last good model kept.
TEST(ProductFiles, HostilePlyIsRefusedWithoutBlocking) {
  const fs::path dir = test::scratchPath("product-hostile");
  fs::create_directories(dir);
  const fs::path file = dir / "bunny.ply";
  std::ofstream(file, std::ios::binary)
      << "ply\nformat binary_little_endian 1.0\ncomment hot-swapped from a USB stick\n"
         "element foo 1000000000000\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n";
  shadow::SceneBundle b;
  b.products = {current()};
  KioskLog log;
  ProductFileWatcher watcher({{"bunny", file}});
  const auto start = std::chrono::steady_clock::now();
  // poll() collects what is ready at once: a refusal this quick may already be applied
  // (under qemu it was, once the loader's code had been translated by an earlier test).
  auto changes = watcher.poll(b, log, 1, ProductFileWatcher::Wait::kNo);
  if (changes.empty()) changes = watcher.collect(b, log, 2, ProductFileWatcher::Wait::kUntilLoaded);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_FALSE(changes[0].replaced);
  EXPECT_NE(changes[0].refusal.find("element foo: 1000000000000 records, more than"),
            std::string::npos)
      << changes[0].refusal;
  EXPECT_EQ(b.products[0].mesh, current().mesh);
  ASSERT_EQ(log.lines().size(), 1u);
  EXPECT_TRUE(log.contains("product bunny: refused " + file.string()));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace penumbra::kiosk
