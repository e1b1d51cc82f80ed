#include "kiosk/product_files.h"

#include <cmath>

#include "scene/mesh_io.h"

namespace penumbra::kiosk {

shadow::ProductModel loadProductFile(const std::filesystem::path& file,
                                     const shadow::ProductModel& current) {
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
  return model;
}

std::string swapProductFile(shadow::SceneBundle& bundle, const ProductFile& swap, KioskLog& log,
                            int64_t nowNs) {
  for (shadow::ProductModel& p : bundle.products) {
    if (p.name != swap.product) continue;
    try {
      p = loadProductFile(swap.file, p);
    } catch (const ProductFileError& e) {
      log.write(
          nowNs, LogLevel::kError,
          "product " + swap.product + ": refused " + e.what() + "; keeping the last good model");
      return e.what();
    }
    log.write(nowNs, LogLevel::kInfo,
              "product " + swap.product + ": model " + swap.file.string() + " (" +
                  std::to_string(p.mesh.triangleCount()) + " triangles)");
    return {};
  }
  throw ProductFileError(swap.file.string() + ": the bundle has no product named '" + swap.product +
                         "'");
}

std::string productFileFault(const std::string& product) {
  return "MODEL REFUSED: " + product;
}

ProductFileWatcher::ProductFileWatcher(std::vector<ProductFile> files) {
  for (ProductFile& f : files) files_.push_back({std::move(f)});
}

std::vector<ProductFileWatcher::Change> ProductFileWatcher::poll(shadow::SceneBundle& bundle,
                                                                 KioskLog& log, int64_t nowNs) {
  std::vector<Change> changes;
  for (Watched& w : files_) {
    std::error_code ec;
    const std::filesystem::file_time_type t = std::filesystem::last_write_time(w.file.file, ec);
    if (w.polled && !ec && t == w.seen) continue;
    if (w.polled && ec && w.seen == std::filesystem::file_time_type{}) continue;  // still absent
    w.polled = true;
    w.seen = ec ? std::filesystem::file_time_type{} : t;
    Change c;
    c.refusal = swapProductFile(bundle, w.file, log, nowNs);
    c.replaced = c.refusal.empty();
    for (uint32_t i = 0; i < bundle.products.size(); ++i) {
      if (bundle.products[i].name == w.file.product) c.product = i;
    }
    changes.push_back(std::move(c));
  }
  return changes;
}

}  // namespace penumbra::kiosk
