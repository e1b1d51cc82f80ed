#include "raster/frame_trace.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

namespace penumbra::raster {
namespace {

// The sidecar is little-endian and read with memcpy: every target we build for is too.
static_assert(std::endian::native == std::endian::little);

using nlohmann::json;

[[noreturn]] void fail(const std::string& where, const std::string& field,
                       const std::string& what) {
  throw TraceError(where + ": " + field + ": " + what);
}

bool finite(const core::Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void validateMatrix(const core::Mat4& m, const std::string& where, const std::string& field) {
  for (float v : m.m) {
    if (!std::isfinite(v)) fail(where, field, "contains a non-finite number");
  }
}

void validateMesh(const core::Mesh& mesh, const std::string& where, const std::string& field) {
  if (mesh.indices.size() % 3 != 0) {
    fail(where, field + ".indices",
         "count " + std::to_string(mesh.indices.size()) + " is not a multiple of 3");
  }
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!finite(mesh.positions[i])) {
      fail(where, field + ".positions", "vertex " + std::to_string(i) + " is not finite");
    }
  }
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      fail(where, field + ".indices",
           "index " + std::to_string(i) + " = " + std::to_string(mesh.indices[i]) +
               " is out of range (" + std::to_string(mesh.positions.size()) + " vertices)");
    }
  }
}

// Receiver triangles of one pass with their S: each in range and listed once (spec §6: a
// triangle listed twice would subtract twice), three colours per triangle.
void validateReceivers(const std::vector<uint32_t>& triangles, const std::vector<core::Rgb8>& s,
                       size_t available, const std::string& where, const std::string& field,
                       const std::string& sField, const char* kind) {
  std::vector<bool> listed(available, false);
  for (uint32_t t : triangles) {
    if (t >= available) {
      fail(where, field,
           "triangle " + std::to_string(t) + " is out of range (" + std::to_string(available) +
               " " + kind + " triangles)");
    }
    if (listed[t]) fail(where, field, "triangle " + std::to_string(t) + " is listed twice");
    listed[t] = true;
  }
  if (s.size() != 3 * triangles.size()) fail(where, sField, "count must be 3 x the triangle count");
}

// --- reading -------------------------------------------------------------------------

struct Reader {
  std::string where;
  const std::vector<uint8_t>* blob;

  const json& need(const json& j, const std::string& key, const std::string& path) const {
    if (!j.is_object() || !j.contains(key)) fail(where, path + key, "missing");
    return j.at(key);
  }

  template <class T>
  T number(const json& j, const std::string& key, const std::string& path) const {
    const json& v = need(j, key, path);
    if (!v.is_number()) fail(where, path + key, "not a number");
    if constexpr (std::is_integral_v<T>) {
      // Views and sizes are below 2^53 in any real file; larger counts are refused.
      constexpr uint64_t kLimit =
          std::min<uint64_t>(std::numeric_limits<T>::max(), uint64_t{1} << 53);
      if (!v.is_number_integer() || v.get<int64_t>() < 0 ||
          static_cast<uint64_t>(v.get<int64_t>()) > kLimit) {
        fail(where, path + key, "not a non-negative integer in range");
      }
      return static_cast<T>(v.get<int64_t>());
    } else {
      return static_cast<T>(v.get<double>());
    }
  }

  core::Mat4 matrix(const json& j, const std::string& key, const std::string& path) const {
    const json& v = need(j, key, path);
    if (!v.is_array() || v.size() != 16) fail(where, path + key, "needs 16 numbers");
    core::Mat4 m;
    for (size_t i = 0; i < 16; ++i) {
      if (!v[i].is_number())
        fail(where, path + key, "element " + std::to_string(i) + " is not a number");
      m.m[i] = static_cast<float>(v[i].get<double>());
    }
    return m;
  }

  // Reads a view of `elementBytes`-byte elements into `out` (resized to count*components).
  template <class T>
  void view(const json& j, const std::string& key, const std::string& path, size_t components,
            std::vector<T>& out) const {
    const json& v = need(j, key, path);
    const std::string field = path + key;
    const auto offset = number<uint64_t>(v, "offset", field + ".");
    const auto count = number<uint64_t>(v, "count", field + ".");
    const uint64_t bytes = count * components * sizeof(T);
    if (count > (uint64_t{1} << 32) || offset > blob->size() || bytes > blob->size() - offset) {
      fail(where, field,
           "view [" + std::to_string(offset) + ", +" + std::to_string(bytes) +
               ") runs past the end of the buffer (" + std::to_string(blob->size()) + " bytes)");
    }
    out.resize(count * components);
    if (bytes > 0) std::memcpy(out.data(), blob->data() + offset, bytes);
  }

  void vec3s(const json& j, const std::string& key, const std::string& path,
             std::vector<core::Vec3>& out) const {
    std::vector<float> flat;
    view(j, key, path, 3, flat);
    out.resize(flat.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  }

  void rgbs(const json& j, const std::string& key, const std::string& path,
            std::vector<core::Rgb8>& out) const {
    std::vector<uint8_t> flat;
    view(j, key, path, 3, flat);
    out.resize(flat.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  }

  core::Mesh mesh(const json& j, const std::string& path) const {
    core::Mesh m;
    vec3s(j, "positions", path, m.positions);
    view(j, "indices", path, 1, m.indices);
    return m;
  }

  const json& array(const json& j, const std::string& key) const {
    const json& v = need(j, key, "");
    if (!v.is_array()) fail(where, key, "not an array");
    return v;
  }
};

// --- writing -------------------------------------------------------------------------

struct Writer {
  std::vector<uint8_t> blob;

  template <class T>
  json view(const T* data, size_t count, size_t components) {
    json v = {{"offset", blob.size()}, {"count", count}};
    const size_t bytes = count * components * sizeof(T);
    const auto* p = reinterpret_cast<const uint8_t*>(data);
    blob.insert(blob.end(), p, p + bytes);
    return v;
  }
  json vec3s(const std::vector<core::Vec3>& v) {
    static_assert(sizeof(core::Vec3) == 12);
    return view(reinterpret_cast<const float*>(v.data()), v.size(), 3);
  }
  json rgbs(const std::vector<core::Rgb8>& v) {
    static_assert(sizeof(core::Rgb8) == 3);
    return view(reinterpret_cast<const uint8_t*>(v.data()), v.size(), 3);
  }
  json mesh(const core::Mesh& m) {
    return {{"positions", vec3s(m.positions)},
            {"indices", view(m.indices.data(), m.indices.size(), 1)}};
  }
};

json matrixJson(const core::Mat4& m) {
  json a = json::array();
  for (float v : m.m) a.push_back(static_cast<double>(v));  // exact: every float is a double
  return a;
}

}  // namespace

void validateTrace(const FrameTrace& trace, const std::string& where) {
  const StaticView& view = trace.view;
  if (view.width < 1 || view.width > kMaxImageSide) fail(where, "width", "must be in 1..4096");
  if (view.height < 1 || view.height > kMaxImageSide) fail(where, "height", "must be in 1..4096");
  validateMatrix(view.cameraViewProj, where, "camera_view_proj");
  validateMesh(view.staticMesh, where, "static_mesh");
  if (view.staticMesh.triangleCount() > kMaxStaticTriangles) {
    fail(where, "static_mesh.indices", "more than 2^31 triangles");
  }
  validateFrame(trace.frame, view.width, view.height, view.staticMesh.triangleCount(), where);
}

void validateFrame(const FrameContent& frame, uint32_t width, uint32_t height,
                   size_t staticTriangles, const std::string& where) {
  const size_t pixels = size_t{width} * height;
  if (frame.background.size() != pixels * 4) {
    fail(where, "background",
         "has " + std::to_string(frame.background.size()) +
             " bytes, expected width*height*4 = " + std::to_string(pixels * 4));
  }
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    const std::string field = "objects[" + std::to_string(i) + "]";
    validateMesh(frame.objects[i].mesh, where, field);
    if (frame.objects[i].colours.size() != frame.objects[i].mesh.positions.size()) {
      fail(where, field + ".colours", "count differs from the vertex count");
    }
  }
  size_t objectTriangles = 0;
  for (const ShadedMesh& o : frame.objects) objectTriangles += o.mesh.triangleCount();
  if (objectTriangles > kMaxObjectTriangles) fail(where, "objects", "too many triangles");
  for (size_t i = 0; i < frame.occluders.size(); ++i) {
    validateMesh(frame.occluders[i], where, "occluders[" + std::to_string(i) + "]");
  }
  // Each pass subtracts at most 255 per channel and the renderer sums them in 16 bits
  // (spec §8): 257 * 255 = 65535.
  if (frame.passes.size() > kMaxPasses) {
    fail(where, "passes",
         std::to_string(frame.passes.size()) + " passes, at most " + std::to_string(kMaxPasses) +
             " are allowed");
  }
  for (size_t i = 0; i < frame.passes.size(); ++i) {
    const ShadowPass& pass = frame.passes[i];
    const std::string field = "passes[" + std::to_string(i) + "]";
    validateMatrix(pass.lightViewProj, where, field + ".light_view_proj");
    if (pass.shadowMapSize < 16 || pass.shadowMapSize > kMaxShadowMapSize ||
        pass.shadowMapSize % 16 != 0) {
      fail(where, field + ".shadow_map_size", "must be a multiple of 16 in 16..4096");
    }
    if (!std::isfinite(pass.depthBias)) fail(where, field + ".depth_bias", "is not finite");
    if (pass.occluder >= frame.occluders.size()) {
      fail(where, field + ".occluder",
           "index " + std::to_string(pass.occluder) + " is out of range");
    }
    validateReceivers(pass.receiverTriangles, pass.receiverS, staticTriangles, where,
                      field + ".receiver_triangles", field + ".receiver_s", "static");
    validateReceivers(pass.objectTriangles, pass.objectS, objectTriangles, where,
                      field + ".object_triangles", field + ".object_s", "object");
    if (!std::isfinite(pass.objectDepthBias)) {
      fail(where, field + ".object_depth_bias", "is not finite");
    }
  }
}

const char* accumulationName(Accumulation a) {
  return a == Accumulation::kFixed8_8 ? "fixed8_8" : "u8";
}

Accumulation parseAccumulation(const std::string& name, const std::string& where) {
  if (name == "u8") return Accumulation::kU8;
  if (name == "fixed8_8") return Accumulation::kFixed8_8;
  throw TraceError(where + ": accumulation: must be \"u8\" or \"fixed8_8\", not \"" + name + "\"");
}

FrameTrace loadTrace(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::ifstream in(path);
  if (!in) throw TraceError(where + ": cannot open file");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::parse_error& e) {
    throw TraceError(where + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object()) throw TraceError(where + ": top level is not a JSON object");
  if (doc.value("format", std::string()) != "penumbra-frame-trace") {
    fail(where, "format", "must be \"penumbra-frame-trace\"");
  }
  if (!doc.contains("version") || doc["version"] != 1) fail(where, "version", "must be 1");
  if (!doc.contains("buffer") || !doc["buffer"].is_string()) fail(where, "buffer", "missing");
  const std::filesystem::path blobPath = path.parent_path() / doc["buffer"].get<std::string>();
  std::vector<uint8_t> blob;
  {
    std::ifstream bin(blobPath, std::ios::binary);
    if (!bin) fail(where, "buffer", "cannot open " + blobPath.string());
    blob.assign(std::istreambuf_iterator<char>(bin), std::istreambuf_iterator<char>());
  }

  Reader r{where, &blob};
  FrameTrace t;
  t.view.width = r.number<uint32_t>(doc, "width", "");
  t.view.height = r.number<uint32_t>(doc, "height", "");
  t.view.cameraViewProj = r.matrix(doc, "camera_view_proj", "");
  t.view.staticMesh = r.mesh(r.need(doc, "static_mesh", ""), "static_mesh.");
  r.view(doc, "background", "", 1, t.frame.background);
  const json& objects = r.array(doc, "objects");
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string p = "objects[" + std::to_string(i) + "].";
    ShadedMesh o;
    o.mesh = r.mesh(objects[i], p);
    r.rgbs(objects[i], "colours", p, o.colours);
    t.frame.objects.push_back(std::move(o));
  }
  const json& occluders = r.array(doc, "occluders");
  for (size_t i = 0; i < occluders.size(); ++i) {
    t.frame.occluders.push_back(r.mesh(occluders[i], "occluders[" + std::to_string(i) + "]."));
  }
  if (doc.contains("accumulation")) {  // optional: "u8" when absent (spec §8)
    if (!doc["accumulation"].is_string()) fail(where, "accumulation", "not a string");
    t.frame.accumulation = parseAccumulation(doc["accumulation"].get<std::string>(), where);
  }
  const json& passes = r.array(doc, "passes");
  for (size_t i = 0; i < passes.size(); ++i) {
    const std::string p = "passes[" + std::to_string(i) + "].";
    const json& pj = passes[i];
    ShadowPass pass;
    pass.lightViewProj = r.matrix(pj, "light_view_proj", p);
    pass.shadowMapSize = r.number<uint32_t>(pj, "shadow_map_size", p);
    pass.depthBias = r.number<float>(pj, "depth_bias", p);
    const json& pcf = r.need(pj, "pcf2x2", p);
    if (!pcf.is_boolean()) fail(where, p + "pcf2x2", "not a boolean");
    pass.pcf2x2 = pcf.get<bool>();
    pass.occluder = r.number<uint32_t>(pj, "occluder", p);
    r.view(pj, "receiver_triangles", p, 1, pass.receiverTriangles);
    r.rgbs(pj, "receiver_s", p, pass.receiverS);
    if (pj.contains("object_triangles")) {  // optional: self-shadowing (§7.2)
      r.view(pj, "object_triangles", p, 1, pass.objectTriangles);
      r.rgbs(pj, "object_s", p, pass.objectS);
      pass.objectDepthBias = r.number<float>(pj, "object_depth_bias", p);
    }
    t.frame.passes.push_back(std::move(pass));
  }
  validateTrace(t, where);
  return t;
}

void saveTrace(const FrameTrace& trace, const std::filesystem::path& path) {
  validateTrace(trace, path.string());
  Writer w;
  json doc;
  const std::filesystem::path blobName = path.stem().string() + ".bin";
  doc["format"] = "penumbra-frame-trace";
  doc["version"] = 1;
  doc["buffer"] = blobName.string();
  doc["width"] = trace.view.width;
  doc["height"] = trace.view.height;
  doc["camera_view_proj"] = matrixJson(trace.view.cameraViewProj);
  doc["static_mesh"] = w.mesh(trace.view.staticMesh);
  doc["background"] = w.view(trace.frame.background.data(), trace.frame.background.size(), 1);
  doc["objects"] = json::array();
  for (const ShadedMesh& o : trace.frame.objects) {
    json oj = w.mesh(o.mesh);
    oj["colours"] = w.rgbs(o.colours);
    doc["objects"].push_back(oj);
  }
  doc["occluders"] = json::array();
  for (const core::Mesh& m : trace.frame.occluders) doc["occluders"].push_back(w.mesh(m));
  doc["accumulation"] = accumulationName(trace.frame.accumulation);
  doc["passes"] = json::array();
  for (const ShadowPass& p : trace.frame.passes) {
    doc["passes"].push_back(
        {{"light_view_proj", matrixJson(p.lightViewProj)},
         {"shadow_map_size", p.shadowMapSize},
         {"depth_bias", static_cast<double>(p.depthBias)},
         {"pcf2x2", p.pcf2x2},
         {"occluder", p.occluder},
         {"receiver_triangles", w.view(p.receiverTriangles.data(), p.receiverTriangles.size(), 1)},
         {"receiver_s", w.rgbs(p.receiverS)}});
    if (!p.objectTriangles.empty()) {
      json& pj = doc["passes"].back();
      pj["object_triangles"] = w.view(p.objectTriangles.data(), p.objectTriangles.size(), 1);
      pj["object_s"] = w.rgbs(p.objectS);
      pj["object_depth_bias"] = static_cast<double>(p.objectDepthBias);
    }
  }
  std::ofstream bin(path.parent_path() / blobName, std::ios::binary);
  bin.write(reinterpret_cast<const char*>(w.blob.data()),
            static_cast<std::streamsize>(w.blob.size()));
  std::ofstream out(path);
  out << doc.dump(1) << "\n";
  if (!bin || !out) throw TraceError(path.string() + ": cannot write trace");
}

}  // namespace penumbra::raster
