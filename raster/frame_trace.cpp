#include "raster/frame_trace.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/json_reader.h"
#include "core/regular_file.h"
#include "raster/matrix4d.h"

namespace penumbra::raster {
namespace {

// The sidecar is little-endian and read with memcpy: every target we build for is too.
static_assert(std::endian::native == std::endian::little);

using nlohmann::json;

bool finite(const core::Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void validateMatrix(const core::Mat4& m, const std::string& where, const std::string& field) {
  for (float v : m.m) {
    if (!std::isfinite(v)) throw TraceError(where, field, "contains a non-finite number");
  }
}

void validateMesh(const core::Mesh& mesh, const std::string& where, const std::string& field) {
  if (mesh.indices.size() % 3 != 0) {
    throw TraceError(where, field + ".indices",
                     "count " + std::to_string(mesh.indices.size()) + " is not a multiple of 3");
  }
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!finite(mesh.positions[i])) {
      throw TraceError(where, field + ".positions",
                       "vertex " + std::to_string(i) + " is not finite");
    }
  }
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      throw TraceError(where, field + ".indices",
                       "index " + std::to_string(i) + " = " + std::to_string(mesh.indices[i]) +
                           " is out of range (" + std::to_string(mesh.positions.size()) +
                           " vertices)");
    }
  }
}

// Receiver triangles of one pass with their S: each in range and listed once (spec §6: a
// triangle listed twice would subtract twice), three colours per triangle.
void validateReceivers(const std::vector<uint32_t>& triangles, const std::vector<core::Rgb16>& s,
                       size_t available, const std::string& where, const std::string& field,
                       const std::string& sField, const char* kind) {
  // The compositor lists a pass's triangles in increasing order: then one comparison per
  // triangle proves them distinct, and the last one bounds them all (this runs for every
  // pass of every frame: a bitmap per pass cost ~0.25 ms of the demo's frame). Any other
  // order takes the bitmap.
  bool increasing = true;
  for (size_t i = 1; i < triangles.size() && increasing; ++i) {
    increasing = triangles[i - 1] < triangles[i];
  }
  const auto outOfRange = [&](uint32_t t) {
    return TraceError(where, field,
                      "triangle " + std::to_string(t) + " is out of range (" +
                          std::to_string(available) + " " + kind + " triangles)");
  };
  if (increasing) {
    if (!triangles.empty() && triangles.back() >= available) throw outOfRange(triangles.back());
  } else {
    std::vector<bool> listed(available, false);
    for (uint32_t t : triangles) {
      if (t >= available) throw outOfRange(t);
      if (listed[t])
        throw TraceError(where, field, "triangle " + std::to_string(t) + " is listed twice");
      listed[t] = true;
    }
  }
  if (s.size() != 3 * triangles.size())
    throw TraceError(where, sField, "count must be 3 x the triangle count");
  // The largest value first (a loop the compiler vectorizes: this runs every frame), the
  // offending one only when there is one.
  uint16_t topR = 0, topG = 0, topB = 0;  // one reduction per channel: the stride-3 loads
  for (const core::Rgb16& c : s) {        // vectorize, a max of three per element did not
    topR = std::max(topR, c.r);
    topG = std::max(topG, c.g);
    topB = std::max(topB, c.b);
  }
  const uint16_t top = std::max(topR, std::max(topG, topB));
  if (top > core::kMaxFineLevel) {
    throw TraceError(where, sField,
                     "value " + std::to_string(top) + " is above " +
                         std::to_string(core::kMaxFineLevel) + " (255 levels in 8.8)");
  }
}

// --- reading -------------------------------------------------------------------------

using core::JsonValue;

// The JSON part of a trace names views into the binary sidecar `blob`.
struct Reader {
  const std::vector<uint8_t>* blob;
  uint64_t maxBytes;    // all views together (kMaxSidecarBytes unless a test says less)
  uint64_t copied = 0;  // bytes of all views read so far (views may overlap)

  // Views and sizes are below 2^53 in any real file; larger counts are refused.
  template <class T>
  static T count(const JsonValue& v) {
    constexpr uint64_t kLimit =
        std::min<uint64_t>(std::numeric_limits<T>::max(), uint64_t{1} << 53);
    return static_cast<T>(v.integer(0, static_cast<int64_t>(kLimit)));
  }

  static core::Mat4 matrix(const JsonValue& v) {
    core::Mat4 m;
    v.floats(m.m);
    return m;
  }

  // Reads a view of `components`-element items of T into `out` (resized to
  // count*components).
  template <class T>
  void view(const JsonValue& v, size_t components, std::vector<T>& out) {
    const auto offset = count<uint64_t>(v["offset"]);
    const auto n = count<uint64_t>(v["count"]);
    const uint64_t bytes = n * components * sizeof(T);
    if (n > (uint64_t{1} << 32) || offset > blob->size() || bytes > blob->size() - offset) {
      v.fail("view [" + std::to_string(offset) + ", +" + std::to_string(bytes) +
             ") runs past the end of the buffer (" + std::to_string(blob->size()) + " bytes)");
    }
    // Views may overlap, so a small sidecar named by many views could still ask for any
    // amount of memory: what all views copy together is bounded too.
    copied += bytes;
    if (copied > maxBytes) {
      v.fail("the views read so far copy " + std::to_string(copied) + " bytes, more than the " +
             std::to_string(maxBytes) + " a frame trace may hold");
    }
    out.resize(n * components);
    if (bytes > 0) std::memcpy(out.data(), blob->data() + offset, bytes);
  }

  void vec3s(const JsonValue& v, std::vector<core::Vec3>& out) {
    std::vector<float> flat;
    view(v, 3, flat);
    out.resize(flat.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  }

  void rgbs(const JsonValue& v, std::vector<core::Rgb8>& out) {
    std::vector<uint8_t> flat;
    view(v, 3, flat);
    out.resize(flat.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  }

  // Intensity transfers S: 8.8 levels (3 x u16) in version 2, whole levels (3 x u8) in
  // version 1, which are the 8.8 values c * 256.
  void transfers(const JsonValue& v, int version, std::vector<core::Rgb16>& out) {
    if (version == 1) {
      std::vector<core::Rgb8> whole;
      rgbs(v, whole);
      out.resize(whole.size());
      for (size_t i = 0; i < out.size(); ++i) out[i] = core::Rgb16::fromLevels(whole[i]);
      return;
    }
    std::vector<uint16_t> flat;
    view(v, 3, flat);
    out.resize(flat.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
  }

  core::Mesh mesh(const JsonValue& v) {
    core::Mesh m;
    vec3s(v["positions"], m.positions);
    view(v["indices"], 1, m.indices);
    return m;
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
  // S in the trace's version: whole levels as 3 x u8 (version 1), else 8.8 as 3 x u16.
  json transfers(const std::vector<core::Rgb16>& v, int version) {
    static_assert(sizeof(core::Rgb16) == 6);
    if (version == 2) return view(reinterpret_cast<const uint16_t*>(v.data()), v.size(), 3);
    std::vector<uint8_t> whole;
    whole.reserve(3 * v.size());
    for (const core::Rgb16& c : v) {
      for (const uint16_t level : {c.r, c.g, c.b})
        whole.push_back(static_cast<uint8_t>(level >> 8));
    }
    return view(whole.data(), v.size(), 3);
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
  if (view.width < 1 || view.width > kMaxImageSide)
    throw TraceError(where, "width", "must be in 1..4096");
  if (view.height < 1 || view.height > kMaxImageSide)
    throw TraceError(where, "height", "must be in 1..4096");
  validateMatrix(view.cameraViewProj, where, "camera_view_proj");
  // The renderer maps window positions back to the world through its inverse (spec §7).
  Mat4d inverse;
  if (!invert(toDouble(view.cameraViewProj), inverse)) {
    throw TraceError(where, "camera_view_proj", "matrix is singular");
  }
  validateMesh(view.staticMesh, where, "static_mesh");
  if (view.staticMesh.triangleCount() > kMaxStaticTriangles) {
    throw TraceError(where, "static_mesh.indices",
                     std::to_string(view.staticMesh.triangleCount()) + " triangles, at most " +
                         std::to_string(kMaxStaticTriangles) + " are allowed");
  }
  validateFrame(trace.frame, view.width, view.height, view.staticMesh.triangleCount(), where);
}

void validateFrame(const FrameContent& frame, uint32_t width, uint32_t height,
                   size_t staticTriangles, const std::string& where) {
  const size_t pixels = size_t{width} * height;
  const size_t tableSize =
      frame.accumulation == Accumulation::kLinear ? kShadeCodes * kShadeSteps : 0;
  if (frame.shadeTable.size() != tableSize) {
    throw TraceError(where, "shade_table",
                     "has " + std::to_string(frame.shadeTable.size()) + " entries, expected " +
                         std::to_string(tableSize) +
                         " (256 codes x 511 shares with linear "
                         "accumulation, none otherwise)");
  }
  if (frame.background.size() != pixels * 4) {
    throw TraceError(where, "background",
                     "has " + std::to_string(frame.background.size()) +
                         " bytes, expected width*height*4 = " + std::to_string(pixels * 4));
  }
  for (size_t i = 0; i < frame.objects.size(); ++i) {
    const std::string field = "objects[" + std::to_string(i) + "]";
    validateMesh(frame.objects[i].mesh, where, field);
    if (frame.objects[i].colours.size() != frame.objects[i].mesh.positions.size()) {
      throw TraceError(where, field + ".colours", "count differs from the vertex count");
    }
  }
  size_t objectTriangles = 0;
  for (const ShadedMesh& o : frame.objects) objectTriangles += o.mesh.triangleCount();
  if (objectTriangles > kMaxObjectTriangles) {
    throw TraceError(where, "objects",
                     std::to_string(objectTriangles) + " triangles in all, at most " +
                         std::to_string(kMaxObjectTriangles) + " are allowed");
  }
  size_t occluderTriangles = 0;
  for (size_t i = 0; i < frame.occluders.size(); ++i) {
    validateMesh(frame.occluders[i], where, "occluders[" + std::to_string(i) + "]");
    occluderTriangles += frame.occluders[i].triangleCount();
  }
  if (occluderTriangles > kMaxOccluderTriangles) {
    throw TraceError(where, "occluders",
                     std::to_string(occluderTriangles) + " triangles in all, at most " +
                         std::to_string(kMaxOccluderTriangles) + " are allowed");
  }
  if (frame.passes.size() > kMaxPasses) {
    throw TraceError(where, "passes",
                     std::to_string(frame.passes.size()) + " passes, at most " +
                         std::to_string(kMaxPasses) + " are allowed");
  }
  for (size_t i = 0; i < frame.passes.size(); ++i) {
    const ShadowPass& pass = frame.passes[i];
    const std::string field = "passes[" + std::to_string(i) + "]";
    validateMatrix(pass.lightViewProj, where, field + ".light_view_proj");
    if (pass.shadowMapSize < 16 || pass.shadowMapSize > kMaxShadowMapSize ||
        pass.shadowMapSize % 16 != 0) {
      throw TraceError(where, field + ".shadow_map_size", "must be a multiple of 16 in 16..4096");
    }
    if (!std::isfinite(pass.depthBias))
      throw TraceError(where, field + ".depth_bias", "is not finite");
    if (pass.occluder >= frame.occluders.size()) {
      throw TraceError(where, field + ".occluder",
                       "index " + std::to_string(pass.occluder) + " is out of range");
    }
    validateReceivers(pass.receiverTriangles, pass.receiverS, staticTriangles, where,
                      field + ".receiver_triangles", field + ".receiver_s", "static");
    validateReceivers(pass.objectTriangles, pass.objectS, objectTriangles, where,
                      field + ".object_triangles", field + ".object_s", "object");
    if (!std::isfinite(pass.objectDepthBias)) {
      throw TraceError(where, field + ".object_depth_bias", "is not finite");
    }
    if (!(pass.penumbraScale >= 0 && pass.penumbraScale < 1e30f)) {
      throw TraceError(where, field + ".penumbra_scale", "must be finite and not negative");
    }
    if (pass.penumbraScale > 0 && (!pass.pcf2x2 || pass.shadowMapSize > kMaxAreaPenumbraMapSize)) {
      throw TraceError(where, field + ".penumbra_scale",
                       "needs pcf2x2 and a shadow map of at most " +
                           std::to_string(kMaxAreaPenumbraMapSize) + " texels");
    }
  }
}

const char* accumulationName(Accumulation a) {
  switch (a) {
    case Accumulation::kFixed8_8:
      return "fixed8_8";
    case Accumulation::kLinear:
      return "linear";
    case Accumulation::kU8:
      break;
  }
  return "u8";
}

Accumulation parseAccumulation(const std::string& name, const std::string& where) {
  for (const Accumulation a : {Accumulation::kU8, Accumulation::kFixed8_8, Accumulation::kLinear}) {
    if (name == accumulationName(a)) return a;
  }
  throw TraceError(where, "accumulation",
                   "expected one of \"u8\", \"fixed8_8\", \"linear\", got \"" + name + "\"");
}

FrameTrace loadTrace(const std::filesystem::path& path, uint64_t maxBytes) {
  const std::string where = path.string();
  const core::JsonDocument doc(path, core::throwAs<TraceError>);
  const JsonValue root = doc.root().object();
  if (root.stringOr("format", "") != "penumbra-frame-trace") {
    doc.fail("format", "must be \"penumbra-frame-trace\"");
  }
  if (!root.has("version") || (root["version"].json() != 1 && root["version"].json() != 2)) {
    doc.fail("version", "must be 1 or 2");
  }
  const int version = root["version"].json() == 1 ? 1 : 2;
  const std::vector<uint8_t> blob = core::readRegularFile(
      core::resolveAgainst(path, root["buffer"].nonEmptyString()), maxBytes,
      "a frame trace's sidecar", core::throwAs<TraceError>, where + ": buffer: ");

  Reader r{&blob, maxBytes};
  FrameTrace t;
  t.view.width = Reader::count<uint32_t>(root["width"]);
  t.view.height = Reader::count<uint32_t>(root["height"]);
  t.view.cameraViewProj = Reader::matrix(root["camera_view_proj"]);
  t.view.staticMesh = r.mesh(root["static_mesh"]);
  r.view(root["background"], 1, t.frame.background);
  for (const JsonValue& oj : root["objects"].array()) {
    ShadedMesh o;
    o.mesh = r.mesh(oj);
    r.rgbs(oj["colours"], o.colours);
    t.frame.objects.push_back(std::move(o));
  }
  for (const JsonValue& occluder : root["occluders"].array()) {
    t.frame.occluders.push_back(r.mesh(occluder));
  }
  // Optional: "u8" when absent (spec §8).
  if (const auto accumulation = root.find("accumulation")) {
    t.frame.accumulation = accumulation->oneOf<Accumulation>({{"u8", Accumulation::kU8},
                                                              {"fixed8_8", Accumulation::kFixed8_8},
                                                              {"linear", Accumulation::kLinear}});
  }
  if (t.frame.accumulation == Accumulation::kLinear) {
    r.view(root["shade_table"], 1, t.frame.shadeTable);
  }
  for (const JsonValue& pj : root["passes"].array(0, kMaxPasses)) {
    ShadowPass pass;
    pass.lightViewProj = Reader::matrix(pj["light_view_proj"]);
    pass.shadowMapSize = Reader::count<uint32_t>(pj["shadow_map_size"]);
    pass.depthBias = static_cast<float>(pj["depth_bias"].number());
    pass.pcf2x2 = pj["pcf2x2"].boolean();
    pass.occluder = Reader::count<uint32_t>(pj["occluder"]);
    if (pj.has("cull_back_faces")) pass.cullBackFaces = pj["cull_back_faces"].boolean();
    if (pj.has("penumbra_scale")) {  // optional: area-light penumbrae
      pass.penumbraScale = static_cast<float>(pj["penumbra_scale"].number());
    }
    r.view(pj["receiver_triangles"], 1, pass.receiverTriangles);
    r.transfers(pj["receiver_s"], version, pass.receiverS);
    if (pj.has("object_triangles")) {  // optional: self-shadowing (§7.2)
      r.view(pj["object_triangles"], 1, pass.objectTriangles);
      r.transfers(pj["object_s"], version, pass.objectS);
      pass.objectDepthBias = static_cast<float>(pj["object_depth_bias"].number());
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
  // Version 1 (S in whole levels, 3 bytes each) while every S is one, so that traces of u8
  // pipelines stay readable by version-1 readers (bench/gl_replay's Mesa build among them).
  bool whole = true;
  for (const ShadowPass& p : trace.frame.passes) {
    for (const auto* list : {&p.receiverS, &p.objectS}) {
      for (const core::Rgb16& c : *list) whole = whole && ((c.r | c.g | c.b) & 0xFF) == 0;
    }
  }
  const int version = whole ? 1 : 2;
  doc["version"] = version;
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
  if (trace.frame.accumulation == Accumulation::kLinear) {
    doc["shade_table"] = w.view(trace.frame.shadeTable.data(), trace.frame.shadeTable.size(), 1);
  }
  doc["passes"] = json::array();
  for (const ShadowPass& p : trace.frame.passes) {
    doc["passes"].push_back(
        {{"light_view_proj", matrixJson(p.lightViewProj)},
         {"shadow_map_size", p.shadowMapSize},
         {"depth_bias", static_cast<double>(p.depthBias)},
         {"pcf2x2", p.pcf2x2},
         {"occluder", p.occluder},
         {"receiver_triangles", w.view(p.receiverTriangles.data(), p.receiverTriangles.size(), 1)},
         {"receiver_s", w.transfers(p.receiverS, version)}});
    if (p.cullBackFaces) doc["passes"].back()["cull_back_faces"] = true;
    if (p.penumbraScale > 0) {
      doc["passes"].back()["penumbra_scale"] = static_cast<double>(p.penumbraScale);
    }
    if (!p.objectTriangles.empty()) {
      json& pj = doc["passes"].back();
      pj["object_triangles"] = w.view(p.objectTriangles.data(), p.objectTriangles.size(), 1);
      pj["object_s"] = w.transfers(p.objectS, version);
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
