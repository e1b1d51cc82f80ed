#include "shadow/scene_bundle.h"

#include <cmath>

#include "scene/bundle_io.h"
#include "scene/portable_trig.h"
#include "shadow/irradiance_volume.h"

namespace penumbra::shadow {
namespace {

using scene::BundleReader;
using scene::BundleWriter;

void addMesh(BundleWriter& w, const std::string& name, const core::Mesh& mesh) {
  w.add<core::Vec3>(name + ".positions", mesh.positions);
  w.add<uint32_t>(name + ".indices", mesh.indices);
}

core::Mesh readMesh(const BundleReader& r, const std::string& name) {
  core::Mesh m;
  m.positions = r.get<core::Vec3>(name + ".positions");
  m.indices = r.get<uint32_t>(name + ".indices");
  if (m.indices.size() % 3 != 0) r.fail(name + ".indices", "count is not a multiple of 3");
  for (uint32_t i : m.indices) {
    if (i >= m.positions.size()) r.fail(name + ".indices", "index out of range");
  }
  for (const core::Vec3& p : m.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      r.fail(name + ".positions", "non-finite position");
    }
  }
  return m;
}

// A product's per-vertex normals and reflectances (version 5): empty or one per mesh vertex;
// normals finite and of unit length to within float rounding of a normalized double (1e-3
// leaves room for any exporter's rounding, and refuses a zero or unnormalized vector);
// reflectances in [0, 1].
void readVertexAttributes(const BundleReader& r, const std::string& p, ProductModel& m) {
  m.normals = r.get<glm::vec3>(p + ".normals");
  m.reflectances = r.get<glm::vec3>(p + ".reflectances");
  const size_t vertices = m.mesh.positions.size();
  if (!m.normals.empty() && m.normals.size() != vertices) {
    r.fail(p + ".normals", std::to_string(m.normals.size()) + " normals for " +
                               std::to_string(vertices) + " vertices");
  }
  if (!m.reflectances.empty() && m.reflectances.size() != vertices) {
    r.fail(p + ".reflectances", std::to_string(m.reflectances.size()) + " reflectances for " +
                                    std::to_string(vertices) + " vertices");
  }
  for (size_t i = 0; i < m.normals.size(); ++i) {
    const glm::vec3& n = m.normals[i];
    const double length = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
    if (!(std::abs(length - 1.0) <= 1e-3)) {
      r.fail(p + ".normals", "normal " + std::to_string(i) + " is not of unit length");
    }
  }
  for (size_t i = 0; i < m.reflectances.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (!(m.reflectances[i][c] >= 0 && m.reflectances[i][c] <= 1)) {
        r.fail(p + ".reflectances", "reflectance " + std::to_string(i) + " is not in [0, 1]");
      }
    }
  }
}

// Product names are stored as one character array with a length per product.
void addNames(BundleWriter& w, const std::vector<ProductModel>& products) {
  std::vector<char> chars;
  std::vector<uint32_t> lengths;
  for (const ProductModel& p : products) {
    chars.insert(chars.end(), p.name.begin(), p.name.end());
    lengths.push_back(static_cast<uint32_t>(p.name.size()));
  }
  w.add<char>("products.names", chars);
  w.add<uint32_t>("products.name_lengths", lengths);
}

}  // namespace

void placeMesh(const core::Mesh& in, const ProductPose& pose, core::Mesh& out) {
  double s, c;
  scene::sinCosDegrees(pose.yawDegrees, s, c);  // not libm: same bits on every machine
  out.indices = in.indices;
  out.positions.resize(in.positions.size());
  for (size_t i = 0; i < in.positions.size(); ++i) {
    const core::Vec3& p = in.positions[i];
    out.positions[i] = {static_cast<float>(c * p.x + s * p.z + pose.x),
                        static_cast<float>(p.y + pose.lift),  // the floor is y = 0
                        static_cast<float>(-s * p.x + c * p.z + pose.z)};
  }
}

void placeNormals(const std::vector<glm::vec3>& in, const ProductPose& pose,
                  std::vector<glm::vec3>& out) {
  double s, c;
  scene::sinCosDegrees(pose.yawDegrees, s, c);  // as placeMesh
  out.resize(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const glm::vec3& n = in[i];
    out[i] = {static_cast<float>(c * n.x + s * n.z), n.y, static_cast<float>(-s * n.x + c * n.z)};
  }
}

std::vector<glm::vec3> shadingNormals(const ProductModel& model, const core::Mesh& placed,
                                      const ProductPose& pose) {
  if (model.normals.empty()) return vertexNormals(placed);
  std::vector<glm::vec3> out;
  placeNormals(model.normals, pose, out);
  return out;
}

scene::PatchMesh patchMeshOf(const SceneBundle& b) {
  scene::PatchMesh m;
  for (const core::Vec3& p : b.view.staticMesh.positions) m.positions.emplace_back(p.x, p.y, p.z);
  m.indices = b.view.staticMesh.indices;
  m.trianglePatch = b.trianglePatch;
  m.normals.assign(m.positions.size(), glm::dvec3(0.0));
  for (const PatchRecord& r : b.patches) {
    scene::Patch p;
    p.centre = glm::dvec3(r.centre);
    p.normal = glm::dvec3(r.normal);
    p.area = r.area;
    p.reflectance = glm::dvec3(r.reflectance);
    p.emission = glm::dvec3(r.emission);
    p.firstTriangle = r.firstTriangle;
    m.patches.push_back(p);
  }
  // Vertices are shared within a quad only, so every triangle of a vertex has its normal.
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    for (int c = 0; c < 3; ++c)
      m.normals[m.indices[3 * t + size_t(c)]] = m.patches[m.trianglePatch[t]].normal;
  }
  return m;
}

void saveBundle(const SceneBundle& b, const std::filesystem::path& path) {
  BundleWriter w(kBundleVersion);
  w.addValue<uint32_t>("view.width", b.view.width);
  w.addValue<uint32_t>("view.height", b.view.height);
  w.addValue<core::Mat4>("view.camera", b.view.cameraViewProj);
  addMesh(w, "view.static_mesh", b.view.staticMesh);
  w.add<uint8_t>("background", b.background);
  w.add<uint32_t>("triangle_patch", b.trianglePatch);
  w.add<PatchRecord>("patches", b.patches);
  const std::array<double, 255> thresholds = b.tone.thresholds();
  w.add<double>("tone.thresholds", thresholds);
  w.add<uint32_t>("sets.sources", b.sets.sources);
  w.add<uint32_t>("sets.receivers", b.sets.receivers);
  w.addValue<double>("sets.power_share", b.sets.powerShare);
  const RadianceTransfers& t = b.transfers;
  w.add<uint32_t>("transfers.receiver_vertices", t.receiverVertices);
  w.add<glm::vec3>("transfers.vertex_radiance", t.vertexRadiance);
  w.add<uint32_t>("transfers.source_start", t.sourceStart);
  w.add<uint32_t>("transfers.entry_vertex", t.entryVertex);
  w.add<glm::vec3>("transfers.entry_transfer", t.entryTransfer);
  w.add<float>("transfers.source_average", t.sourceAverage);
  w.addValue<uint32_t>("products.count", static_cast<uint32_t>(b.products.size()));
  addNames(w, b.products);
  for (size_t i = 0; i < b.products.size(); ++i) {
    const std::string p = "products." + std::to_string(i);
    addMesh(w, p + ".mesh", b.products[i].mesh);
    addMesh(w, p + ".proxy", b.products[i].proxy);
    addMesh(w, p + ".fine_proxy", b.products[i].fineProxy);
    w.add<glm::vec3>(p + ".normals", b.products[i].normals);
    w.add<glm::vec3>(p + ".reflectances", b.products[i].reflectances);
    w.addValue<glm::vec3>(p + ".reflectance", b.products[i].reflectance);
    w.addValue<glm::vec3>(p + ".specular", b.products[i].specular);
    w.addValue<float>(p + ".specular_exponent", b.products[i].specularExponent);
  }
  w.addValue<ProductPose>("start_pose", b.startPose);
  const IrradianceVolume& v = b.irradiance;
  w.addValue<glm::uvec3>("irradiance.dims", v.dims);
  w.addValue<glm::vec3>("irradiance.origin", v.origin);
  w.addValue<glm::vec3>("irradiance.spacing", v.spacing);
  w.add<float>("irradiance.coefficients", v.coefficients);
  w.add<uint8_t>("irradiance.valid", v.valid);
  w.add<float>("irradiance.fallback", v.fallback);
  w.add<glm::vec3>("patch_radiance", b.patchRadiance);
  const RenderSettings& rs = b.settings;
  w.addValue<uint32_t>("settings.max_passes", rs.maxPasses);
  w.addValue<uint32_t>("settings.shadow_map_size", rs.shadowMapSize);
  w.addValue<uint32_t>("settings.fine_proxy_passes", rs.fineProxyPasses);
  w.add<uint32_t>("settings.product_fine_proxy_passes", rs.productFineProxyPasses);
  w.addValue<uint32_t>("settings.area_penumbrae", rs.areaPenumbrae ? 1u : 0u);
  w.addValue<uint32_t>("settings.tuned", rs.tuned ? 1u : 0u);
  w.addValue<double>("settings.prune_fraction", rs.pruneFraction);
  w.addValue<uint32_t>("settings.receivers_per_leaf", rs.receiversPerLeaf);
  w.addValue<double>("settings.texels_per_shadow_pixel", rs.texelsPerShadowPixel);
  w.write(path);
}

SceneBundle loadBundle(const std::filesystem::path& path) {
  const BundleReader r(path, kOldestBundleVersion, kBundleVersion);
  SceneBundle b;
  b.view.width = r.getValue<uint32_t>("view.width");
  b.view.height = r.getValue<uint32_t>("view.height");
  b.view.cameraViewProj = r.getValue<core::Mat4>("view.camera");
  b.view.staticMesh = readMesh(r, "view.static_mesh");
  b.background = r.get<uint8_t>("background");
  b.trianglePatch = r.get<uint32_t>("triangle_patch");
  b.patches = r.get<PatchRecord>("patches");
  const std::vector<double> thresholds = r.get<double>("tone.thresholds");
  if (thresholds.size() != 255) r.fail("tone.thresholds", "needs 255 values");
  std::array<double, 255> t{};
  std::copy(thresholds.begin(), thresholds.end(), t.begin());
  try {
    b.tone = ToneCurve::fromThresholds(t);
  } catch (const std::invalid_argument& e) {
    r.fail("tone.thresholds", e.what());
  }
  b.sets.sources = r.get<uint32_t>("sets.sources");
  b.sets.receivers = r.get<uint32_t>("sets.receivers");
  b.sets.powerShare = r.getValue<double>("sets.power_share");
  RadianceTransfers& x = b.transfers;
  x.receiverVertices = r.get<uint32_t>("transfers.receiver_vertices");
  x.vertexRadiance = r.get<glm::vec3>("transfers.vertex_radiance");
  x.sourceStart = r.get<uint32_t>("transfers.source_start");
  x.entryVertex = r.get<uint32_t>("transfers.entry_vertex");
  x.entryTransfer = r.get<glm::vec3>("transfers.entry_transfer");
  x.sourceAverage = r.get<float>("transfers.source_average");
  const uint32_t productCount = r.getValue<uint32_t>("products.count");
  const std::vector<char> names = r.get<char>("products.names");
  const std::vector<uint32_t> lengths = r.get<uint32_t>("products.name_lengths");
  if (lengths.size() != productCount) r.fail("products.name_lengths", "count mismatch");
  size_t at = 0;
  for (uint32_t i = 0; i < productCount; ++i) {
    const std::string p = "products." + std::to_string(i);
    ProductModel m;
    if (lengths[i] > names.size() - at) r.fail("products.names", "too short");
    m.name.assign(names.begin() + std::ptrdiff_t(at),
                  names.begin() + std::ptrdiff_t(at + lengths[i]));
    at += lengths[i];
    m.mesh = readMesh(r, p + ".mesh");
    m.proxy = readMesh(r, p + ".proxy");
    if (r.version() >= 6) m.fineProxy = readMesh(r, p + ".fine_proxy");
    if (r.version() >= 5) readVertexAttributes(r, p, m);
    m.reflectance = r.getValue<glm::vec3>(p + ".reflectance");
    m.specular = r.getValue<glm::vec3>(p + ".specular");
    m.specularExponent = r.getValue<float>(p + ".specular_exponent");
    for (int c = 0; c < 3; ++c) {
      if (!(m.reflectance[c] >= 0 && m.reflectance[c] <= 1)) {
        r.fail(p + ".reflectance", "not in [0, 1]");
      }
      if (!(m.specular[c] >= 0 && m.specular[c] <= 1)) r.fail(p + ".specular", "not in [0, 1]");
    }
    if (!(m.specularExponent >= 0 && std::isfinite(m.specularExponent))) {
      r.fail(p + ".specular_exponent", "not finite and >= 0");
    }
    b.products.push_back(std::move(m));
  }
  b.startPose = r.getValue<ProductPose>("start_pose");
  IrradianceVolume& vol = b.irradiance;
  vol.dims = r.getValue<glm::uvec3>("irradiance.dims");
  vol.origin = r.getValue<glm::vec3>("irradiance.origin");
  vol.spacing = r.getValue<glm::vec3>("irradiance.spacing");
  vol.coefficients = r.get<float>("irradiance.coefficients");
  vol.valid = r.get<uint8_t>("irradiance.valid");
  const std::vector<float> fallback = r.get<float>("irradiance.fallback");
  if (fallback.size() != vol.fallback.size()) r.fail("irradiance.fallback", "needs 27 values");
  std::copy(fallback.begin(), fallback.end(), vol.fallback.begin());
  if (!vol.empty()) {
    // A volume is optional (empty: form-factor shading), but a present one must be whole.
    if (vol.dims.x > 1024 || vol.dims.y > 1024 || vol.dims.z > 1024 ||
        vol.vertexCount() > (size_t{1} << 22)) {
      r.fail("irradiance.dims", "too many grid vertices");
    }
    try {
      vol.validate();
    } catch (const std::invalid_argument& e) {
      r.fail("irradiance", e.what());
    }
  } else if (!vol.valid.empty()) {
    r.fail("irradiance.valid", "flags without coefficients");
  }
  b.patchRadiance = r.get<glm::vec3>("patch_radiance");
  if (!b.patchRadiance.empty() && b.patchRadiance.size() != b.patches.size()) {
    r.fail("patch_radiance", "one entry per patch");
  }
  for (const glm::vec3& l : b.patchRadiance) {
    for (int c = 0; c < 3; ++c) {
      if (!(l[c] >= 0 && std::isfinite(l[c]))) r.fail("patch_radiance", "negative or not finite");
    }
  }

  if (r.version() >= 7) {
    RenderSettings& rs = b.settings;
    rs.maxPasses = r.getValue<uint32_t>("settings.max_passes");
    rs.shadowMapSize = r.getValue<uint32_t>("settings.shadow_map_size");
    rs.fineProxyPasses = r.getValue<uint32_t>("settings.fine_proxy_passes");
    const auto flag = [&](const std::string& name) {
      const uint32_t v = r.getValue<uint32_t>(name);
      if (v > 1) r.fail(name, "is " + std::to_string(v) + ", not 0 or 1");
      return v == 1;
    };
    rs.areaPenumbrae = flag("settings.area_penumbrae");
    rs.tuned = flag("settings.tuned");
    if (r.version() >= 8) {
      rs.pruneFraction = r.getValue<double>("settings.prune_fraction");
      rs.receiversPerLeaf = r.getValue<uint32_t>("settings.receivers_per_leaf");
    }
    if (r.version() >= 9) {
      rs.productFineProxyPasses = r.get<uint32_t>("settings.product_fine_proxy_passes");
    }
    if (r.version() >= 10) {
      rs.texelsPerShadowPixel = r.getValue<double>("settings.texels_per_shadow_pixel");
    }
    try {
      validateRenderSettings(rs, b.products.size());
    } catch (const std::invalid_argument& e) {
      r.fail("settings", e.what());
    }
  }

  // Cross-checks: every index the per-frame path follows must be in range.
  const size_t triangles = b.view.staticMesh.triangleCount();
  // What `penumbra precompute` refuses to write (lighting/precompute.h), refused here too:
  // the frame path has nothing to shade without a room or without a receiver the camera
  // sees, and a kiosk must fall back to its last good bundle instead of crashing (issue 18).
  if (triangles == 0) r.fail("view.static_mesh", "no triangles (a bundle needs a room)");
  if (b.sets.receivers.empty()) {
    r.fail("sets.receivers", "none (the camera sees no surface of the room)");
  }
  if (b.background.size() != size_t{b.view.width} * b.view.height * 4) {
    r.fail("background", "size does not match the view");
  }
  if (b.trianglePatch.size() != triangles) r.fail("triangle_patch", "one entry per triangle");
  for (uint32_t p : b.trianglePatch) {
    if (p >= b.patches.size()) r.fail("triangle_patch", "patch index out of range");
  }
  for (const PatchRecord& p : b.patches) {
    if (size_t{p.firstTriangle} + 1 >= triangles) r.fail("patches", "triangle index out of range");
  }
  for (uint32_t s : b.sets.sources) {
    if (s >= b.patches.size()) r.fail("sets.sources", "patch index out of range");
  }
  for (uint32_t s : b.sets.receivers) {
    if (s >= b.patches.size()) r.fail("sets.receivers", "patch index out of range");
  }
  if (x.vertexRadiance.size() != x.receiverVertices.size()) {
    r.fail("transfers.vertex_radiance", "one entry per receiver vertex");
  }
  for (uint32_t v : x.receiverVertices) {
    if (v >= b.view.staticMesh.positions.size()) {
      r.fail("transfers.receiver_vertices", "vertex index out of range");
    }
  }
  if (x.sourceStart.size() != b.sets.sources.size() + 1 || x.sourceStart.front() != 0 ||
      x.sourceStart.back() != x.entryVertex.size()) {
    r.fail("transfers.source_start", "does not match the sources and entries");
  }
  for (size_t s = 1; s < x.sourceStart.size(); ++s) {
    if (x.sourceStart[s] < x.sourceStart[s - 1]) r.fail("transfers.source_start", "decreasing");
  }
  if (x.entryTransfer.size() != x.entryVertex.size()) {
    r.fail("transfers.entry_transfer", "one entry per transfer");
  }
  for (uint32_t v : x.entryVertex) {
    if (v >= x.receiverVertices.size()) r.fail("transfers.entry_vertex", "out of range");
  }
  if (x.sourceAverage.size() != b.sets.sources.size()) {
    r.fail("transfers.source_average", "one entry per source");
  }
  if (b.startPose.product >= b.products.size()) r.fail("start_pose", "product out of range");
  return b;
}

}  // namespace penumbra::shadow
