#include "kiosk/product_files.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "scene/mesh_io.h"
#include "scene/product_size.h"

namespace penumbra::kiosk {

shadow::ProductModel loadProductFile(const std::filesystem::path& file,
                                     const shadow::ProductModel& current,
                                     std::vector<std::string>* warnings) {
  const std::string name = file.string();
  scene::TriangleMesh mesh;
  try {
    mesh = scene::loadMesh(file);
  } catch (const std::exception& e) {
    // The loaders' messages already start with the file name.
    const std::string what = e.what();
    throw ProductFileError(what.rfind(name, 0) == 0 ? what : name + ": " + what);
  }
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::dvec3& p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw ProductFileError(name + ": vertex " + std::to_string(i + 1) + " is not finite");
    }
  }
  if (mesh.triangleCount() == 0) throw ProductFileError(name + ": no triangles");
  if (mesh.triangleCount() > kMaxProductFileTriangles) {
    throw ProductFileError(name + ": " + std::to_string(mesh.triangleCount()) +
                           " triangles; at most " + std::to_string(kMaxProductFileTriangles) +
                           " on the board (simplify it with `penumbra precompute`)");
  }
  const scene::Aabb b = mesh.bounds();
  const glm::dvec3 size = b.max - b.min;
  if (size.x > 10 || size.y > 10 || size.z > 10) {
    throw ProductFileError(name + ": larger than 10 m (metres expected, y up)");
  }
  if (warnings) {
    *warnings = mesh.warnings;
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (const auto w = scene::productSizeWarning(name, std::max({size.x, size.y, size.z}), 1.0,
                                                 ext == ".gltf" || ext == ".glb")) {
      warnings->push_back(*w);
    }
  }
  // As scene_file.cpp places products: footprint centred on the origin, resting on y = 0.
  const glm::dvec3 shift(-b.centre().x, -b.min.y, -b.centre().z);
  shadow::ProductModel model = current;
  model.mesh.positions.clear();
  for (const glm::dvec3& p : mesh.positions) {
    const glm::dvec3 q = p + shift;
    model.mesh.positions.push_back(
        {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)});
  }
  model.mesh.indices = mesh.indices;
  model.proxy = model.mesh;
  model.normals.clear();
  for (const glm::dvec3& n : mesh.normals) model.normals.push_back(glm::vec3(n));
  // The file's colours, or (none) the product's material's one reflectance.
  model.reflectances.clear();
  for (const glm::dvec3& r : mesh.reflectances) model.reflectances.push_back(glm::vec3(r));
  return model;
}

namespace {

// The bundle's product `swap` replaces; throws ProductFileError when there is none.
uint32_t productIndex(const shadow::SceneBundle& bundle, const ProductFile& swap) {
  for (uint32_t i = 0; i < bundle.products.size(); ++i) {
    if (bundle.products[i].name == swap.product) return i;
  }
  throw ProductFileError(swap.file.string() + ": the bundle has no product named '" + swap.product +
                         "'");
}

// Never throws: every failure, an allocation one included, is a refusal.
ProductFileWatcher::Loaded loadOrRefuse(const std::filesystem::path& file,
                                        const shadow::ProductModel& current) {
  try {
    ProductFileWatcher::Loaded loaded;
    loaded.model = loadProductFile(file, current, &loaded.warnings);
    return loaded;
  } catch (const ProductFileError& e) {
    return {{}, e.what(), {}};
  } catch (const std::exception& e) {
    return {{}, file.string() + ": " + e.what(), {}};
  }
}

// Replaces `product` by a loaded model or logs the refusal (one line) and keeps it.
std::string apply(shadow::ProductModel& product, const ProductFile& swap,
                  ProductFileWatcher::Loaded loaded, KioskLog& log, int64_t nowNs) {
  if (!loaded.refusal.empty()) {
    log.write(nowNs, LogLevel::kError,
              "product " + swap.product + ": refused " + loaded.refusal +
                  "; keeping the last good model");
    return loaded.refusal;
  }
  for (const std::string& w : loaded.warnings) {
    log.write(nowNs, LogLevel::kWarning, "product " + swap.product + ": " + w);
  }
  product = std::move(loaded.model);
  log.write(nowNs, LogLevel::kInfo,
            "product " + swap.product + ": model " + swap.file.string() + " (" +
                std::to_string(product.mesh.triangleCount()) + " triangles)");
  return {};
}

}  // namespace

std::string swapProductFile(shadow::SceneBundle& bundle, const ProductFile& swap, KioskLog& log,
                            int64_t nowNs) {
  shadow::ProductModel& p = bundle.products[productIndex(bundle, swap)];
  return apply(p, swap, loadOrRefuse(swap.file, p), log, nowNs);
}

std::string productFileFault(const std::string& product) {
  return "MODEL REFUSED: " + product;
}

ProductFileWatcher::ProductFileWatcher(std::vector<ProductFile> files) {
  for (ProductFile& f : files) files_.push_back({std::move(f), {}, false, {}});
}

ProductFileWatcher::~ProductFileWatcher() = default;  // a std::async future waits for its load

std::vector<ProductFileWatcher::Change> ProductFileWatcher::poll(shadow::SceneBundle& bundle,
                                                                 KioskLog& log, int64_t nowNs,
                                                                 Wait wait) {
  for (Watched& w : files_) {
    if (w.load.valid()) continue;
    std::error_code ec;
    const std::filesystem::file_time_type t = std::filesystem::last_write_time(w.file.file, ec);
    if (w.polled && !ec && t == w.seen) continue;
    if (w.polled && ec && w.seen == std::filesystem::file_time_type{}) continue;  // still absent
    w.polled = true;
    w.seen = ec ? std::filesystem::file_time_type{} : t;
    // The worker reads the file and places the model on a copy of the product (its name and
    // material); the bundle stays the frame thread's.
    w.load = std::async(std::launch::async, loadOrRefuse, w.file.file,
                        bundle.products[productIndex(bundle, w.file)]);
  }
  return collect(bundle, log, nowNs, wait);
}

std::vector<ProductFileWatcher::Change> ProductFileWatcher::collect(shadow::SceneBundle& bundle,
                                                                    KioskLog& log, int64_t nowNs,
                                                                    Wait wait) {
  std::vector<Change> changes;
  for (Watched& w : files_) {
    if (!w.load.valid()) continue;
    if (wait == Wait::kNo &&
        w.load.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      continue;
    }
    Change c;
    c.product = productIndex(bundle, w.file);
    c.refusal = apply(bundle.products[c.product], w.file, w.load.get(), log, nowNs);
    c.replaced = c.refusal.empty();
    changes.push_back(std::move(c));
  }
  return changes;
}

bool ProductFileWatcher::loading() const {
  return std::any_of(files_.begin(), files_.end(), [](const Watched& w) { return w.load.valid(); });
}

}  // namespace penumbra::kiosk
