#include "bench/gl_replay/gl_trace_replay.h"

#include <GLES3/gl32.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "bench/gl_replay/gl_context.h"
#include "bench/gl_replay/gl_util.h"
#include "raster/matrix4d.h"

namespace penumbra::gl {
namespace {

using raster::AttributePlane;
using raster::SetupTriangle;
using Vertex = GlTraceReplay::Vertex;
using MapVertex = GlTraceReplay::MapVertex;

// Every geometry draw: the snapped vertex as given (w = 1: nothing left for GL to clip in
// its guard-band-free viewport, gl_coverage.cpp), the triangle's constants passed flat. Each
// program declares only the constants it reads (WITH_ID, WITH_LEVELS): llvmpipe sets up
// every varying of every triangle, and shadow-map triangles are many and small.
const char* const kGeometryVertex = R"(
layout(location = 0) in vec2 position;
layout(location = 1) in vec3 depthPlane;
layout(location = 2) in ivec2 origin;
flat out vec3 vDepthPlane;
flat out ivec2 vOrigin;
#ifdef WITH_ID
layout(location = 3) in uint id;
flat out uint vId;
#endif
#ifdef WITH_LEVELS
layout(location = 4) in uvec3 planeC;
layout(location = 5) in uvec3 planeGx;
layout(location = 6) in uvec3 planeGy;
flat out uvec3 vC, vGx, vGy;
#endif
void main() {
  gl_Position = vec4(position, 0.0, 1.0);
  vDepthPlane = depthPlane;
  vOrigin = origin;
#ifdef WITH_ID
  vId = id;
#endif
#ifdef WITH_LEVELS
  vC = planeC;
  vGx = planeGx;
  vGy = planeGy;
#endif
}
)";

// Spec §5, shared by every fragment shader: the depth plane in binary32, left to right,
// without contraction (`precise`), and the 8.16 planes in wrapping uint arithmetic rounded
// to whole levels with an arithmetic shift of the int32 value.
const char* const kPlanes = R"(
precision highp float;
precision highp int;
flat in vec3 vDepthPlane;
flat in ivec2 vOrigin;
float planeDepth(ivec2 p) {
  precise float z = (vDepthPlane.x + vDepthPlane.y * float(p.x - vOrigin.x)) +
                    vDepthPlane.z * float(p.y - vOrigin.y);
  return z;
}
#ifdef WITH_ID
flat in uint vId;
#endif
#ifdef WITH_LEVELS
flat in uvec3 vC, vGx, vGy;
uvec3 planeLevels(ivec2 p) {
  uint fx = uint(p.x - vOrigin.x), fy = uint(p.y - vOrigin.y);
  uvec3 v = vC + vGx * fx + vGy * fy;
  return uvec3(clamp(ivec3(v + 0x8000u) >> 16, 0, 255));
}
#endif
)";

// Shadow maps, room and objects: depth z / 2 (1.0, the clear value, is +inf), and in the
// frame the id and for objects the colour (spec §6 steps 1–3). One program each, so that
// none computes what its target drops.
const char* const kMapFragment =
    "void main() { gl_FragDepth = planeDepth(ivec2(gl_FragCoord.xy)) * 0.5; }\n";

const char* const kRoomFragment =
    "layout(location = 1) out uint idOut;\n"
    "void main() {\n"
    "  gl_FragDepth = planeDepth(ivec2(gl_FragCoord.xy)) * 0.5;\n"
    "  idOut = vId;\n"
    "}\n";

const char* const kObjectFragment =
    "layout(location = 0) out vec4 colour;\n"
    "layout(location = 1) out uint idOut;\n"
    "void main() {\n"
    "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
    "  gl_FragDepth = planeDepth(p) * 0.5;\n"
    "  colour = vec4(vec3(planeLevels(p)) / 255.0, 1.0);\n"
    "  idOut = vId;\n"
    "}\n";

// Spec §6 step 4 and §7 at one receiver pixel: the id test, S, the mask from the texel
// values, round(S M / 255) exactly, written for the reverse-subtract blend.
const char* const kPassFragment =
    R"(
uniform highp usampler2D ids;
uniform highp sampler2D shadowMap;  // z / 2 per texel, 1.0 where nothing was drawn (+inf)
uniform vec4 p0, p1, p2, p3;        // rows of spec §7's P
uniform int mapSize;
uniform float depthBias;
uniform bool pcf2x2;
out vec4 colour;
bool occludes(int i, int j, float d) {
  if (i < 0 || i >= mapSize || j < 0 || j >= mapSize) return false;
  float stored = texelFetch(shadowMap, ivec2(i, j), 0).r;
  if (stored == 1.0) return false;  // +inf + bias: never occludes
  precise float limit = stored * 2.0 + depthBias;
  return d > limit;
}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (texelFetch(ids, p, 0).r != vId) discard;
  // S = 0 subtracts nothing whatever the mask: no lookup (the showroom's many zero corners).
  uvec3 s = planeLevels(p);
  if (s == uvec3(0u)) discard;
  float z = planeDepth(p);
  float sx = float(p.x) + 0.5, sy = float(p.y) + 0.5;
  precise float q0 = ((p0.x * sx + p0.y * sy) + p0.z * z) + p0.w;
  precise float q1 = ((p1.x * sx + p1.y * sy) + p1.z * z) + p1.w;
  precise float q2 = ((p2.x * sx + p2.y * sy) + p2.z * z) + p2.w;
  precise float q3 = ((p3.x * sx + p3.y * sy) + p3.z * z) + p3.w;
  int w = 0;
  if (q3 > 0.0) {
    precise float u = q0 / q3;
    precise float v = q1 / q3;
    precise float d = q2 / q3;
    float size = float(mapSize);
    if (!pcf2x2) {
      if (u >= 0.0 && u < size && v >= 0.0 && v < size) {
        w = occludes(int(u), int(v), d) ? 65536 : 0;
      }
    } else {
      precise float up = u - 0.5;
      precise float vp = v - 0.5;
      if (up > -1.0 && up < size && vp > -1.0 && vp < size) {
        float fu = floor(up), fv = floor(vp);
        int i = int(fu), j = int(fv);
        precise float wuf = (up - fu) * 256.0 + 0.5;
        precise float wvf = (vp - fv) * 256.0 + 0.5;
        int wu = int(wuf), wv = int(wvf);
        w = (occludes(i, j, d) ? (256 - wu) * (256 - wv) : 0) +
            (occludes(i + 1, j, d) ? wu * (256 - wv) : 0) +
            (occludes(i, j + 1, d) ? (256 - wu) * wv : 0) +
            (occludes(i + 1, j + 1, d) ? wu * wv : 0);
      }
    }
  }
  uint m = (255u * uint(w) + 32768u) >> 16;
  uvec3 amount = (s * m * 257u + 0x8080u) >> 16;
  colour = vec4(vec3(amount) / 255.0, 0.0);
}
)";

const char* const kBackgroundVertex = R"(#version 320 es
void main() {
  vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID >> 1) * 4 - 1));
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

const char* const kBackgroundFragment = R"(#version 320 es
precision highp float;
uniform highp sampler2D background;
layout(location = 0) out vec4 colour;
void main() { colour = texelFetch(background, ivec2(gl_FragCoord.xy), 0); }
)";

uint32_t pow2Side(uint32_t n) {
  uint32_t p = 1;
  while (p < n) p *= 2;
  return p;
}

// A byte offset into the bound GL_ARRAY_BUFFER, which glVertexAttrib*Pointer takes as a
// pointer (the GL API's convention, not an address).
const void* bufferOffset(size_t offset) {
  return reinterpret_cast<const void*>(offset);  // NOLINT(performance-no-int-to-ptr)
}

void bindVertexLayout() {
  const auto stride = static_cast<GLsizei>(sizeof(Vertex));
  auto at = bufferOffset;
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, stride, at(offsetof(Vertex, x)));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, at(offsetof(Vertex, z00)));
  glVertexAttribIPointer(2, 2, GL_INT, stride, at(offsetof(Vertex, ox)));
  glVertexAttribIPointer(3, 1, GL_UNSIGNED_INT, stride, at(offsetof(Vertex, id)));
  glVertexAttribIPointer(4, 3, GL_UNSIGNED_INT, stride, at(offsetof(Vertex, c)));
  glVertexAttribIPointer(5, 3, GL_UNSIGNED_INT, stride, at(offsetof(Vertex, gx)));
  glVertexAttribIPointer(6, 3, GL_UNSIGNED_INT, stride, at(offsetof(Vertex, gy)));
  for (GLuint i = 0; i < 7; ++i) glEnableVertexAttribArray(i);
}

// The geometry vertex shader and `fragment` with the constants WITH_ID / WITH_LEVELS.
GLuint geometryProgram(const char* fragment, bool withId, bool withLevels,
                       const std::string& name) {
  std::string head = "#version 320 es\n";
  if (withId) head += "#define WITH_ID 1\n";
  if (withLevels) head += "#define WITH_LEVELS 1\n";
  const std::string vertex = head + kGeometryVertex;
  const std::string fragmentSource = head + kPlanes + fragment;
  return detail::buildProgram(vertex.c_str(), fragmentSource.c_str(), name);
}

void bindMapLayout() {
  const auto stride = static_cast<GLsizei>(sizeof(MapVertex));
  auto at = bufferOffset;
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, stride, at(offsetof(MapVertex, x)));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, at(offsetof(MapVertex, z00)));
  glVertexAttribIPointer(2, 2, GL_INT, stride, at(offsetof(MapVertex, ox)));
  for (GLuint i = 0; i < 3; ++i) glEnableVertexAttribArray(i);
}

void setViewport(uint32_t side, int32_t origin) {
  glViewport(origin, origin, static_cast<GLsizei>(side), static_cast<GLsizei>(side));
}

}  // namespace

core::Mat4 windowToLightTexel(const core::Mat4& camera, uint32_t width, uint32_t height,
                              const core::Mat4& light, uint32_t shadowMapSize) {
  // The same products in the same order as raster/renderer.cpp (spec §7).
  raster::Mat4d cameraInverse;
  if (!raster::invert(raster::toDouble(camera), cameraInverse)) {
    throw std::invalid_argument("singular camera matrix");
  }
  const double hw = width / 2.0, hh = height / 2.0, half = shadowMapSize / 2.0;
  const raster::Mat4d viewportInverse = {1.0 / hw, 0, 0, -1, 0, -1.0 / hh, 0, 1,
                                         0,        0, 2, -1, 0, 0,         0, 1};
  const raster::Mat4d windowToWorld = raster::multiply(cameraInverse, viewportInverse);
  const raster::Mat4d toTexel = {half, 0, 0, half, 0, -half, 0, half, 0, 0, 0.5, 0.5, 0, 0, 0, 1};
  const raster::Mat4d p =
      raster::multiply(raster::multiply(toTexel, raster::toDouble(light)), windowToWorld);
  core::Mat4 out;
  for (size_t i = 0; i < 16; ++i) out.m[i] = static_cast<float>(p[i]);
  return out;
}

GlTraceReplay::Target GlTraceReplay::targetFor(uint32_t width, uint32_t height) {
  // gl_coverage.cpp: a viewport up to 8x the image's power-of-two side, centred on it, so
  // that llvmpipe never clips a guard-band vertex (spec §3: |x| <= 4w is 1.5 images beyond
  // either side) and every NDC coordinate below is exact.
  const uint32_t side = pow2Side(std::max(width, height));
  GLint maxViewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
  const auto maxSide = static_cast<uint32_t>(std::min(maxViewport[0], maxViewport[1]));
  if (maxSide < side) throw GlError("GlTraceReplay: image larger than GL_MAX_VIEWPORT_DIMS");
  uint32_t factor = 8;
  while (factor > 1 && side * factor > maxSide) factor /= 2;
  return Target{side * factor, -static_cast<int32_t>(side * (factor - 1) / 2)};
}

void GlTraceReplay::emit(const SetupTriangle& t, const Target& target, uint32_t id,
                         const AttributePlane* planes, std::vector<Vertex>& out) const {
  // Window = origin + (ndc + 1) side / 2 with side a power of two: X / 256 is exact in
  // binary32, and so are ndc and Mesa's viewport transform back (gl_coverage.cpp).
  const double scale = 128.0 * target.side, origin = 256.0 * target.origin;
  for (const raster::SnappedVertex& s : t.v) {
    Vertex v;
    v.x = static_cast<float>((s.x - origin) / scale - 1.0);
    v.y = static_cast<float>((s.y - origin) / scale - 1.0);
    v.z00 = t.depth.z00;
    v.dzdx = t.depth.dzdx;
    v.dzdy = t.depth.dzdy;
    v.ox = t.originX();
    v.oy = t.originY();
    v.id = id;
    if (planes != nullptr) {
      for (size_t c = 0; c < 3; ++c) {
        v.c[c] = planes[c].c;
        v.gx[c] = planes[c].gx;
        v.gy[c] = planes[c].gy;
      }
    }
    out.push_back(v);
  }
}

GlTraceReplay::GlTraceReplay(const raster::StaticView& view) : view_(view) {
  mapProgram_ = geometryProgram(kMapFragment, false, false, "shadow maps");
  roomProgram_ = geometryProgram(kRoomFragment, true, false, "room");
  objectProgram_ = geometryProgram(kObjectFragment, true, true, "objects");
  passProgram_ = geometryProgram(kPassFragment, true, true, "mask and subtract");
  backgroundProgram_ = detail::buildProgram(kBackgroundVertex, kBackgroundFragment, "background");
  frameTarget_ = targetFor(view_.width, view_.height);

  const auto w = static_cast<GLsizei>(view_.width), h = static_cast<GLsizei>(view_.height);
  auto texture = [&](unsigned& name, GLenum format) {
    glGenTextures(1, &name);
    glBindTexture(GL_TEXTURE_2D, name);
    glTexStorage2D(GL_TEXTURE_2D, 1, format, w, h);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  };
  texture(frameColour_, GL_RGBA8);
  texture(frameIds_, GL_R32UI);
  texture(backgroundTexture_, GL_RGBA8);
  glGenRenderbuffers(1, &frameDepth_);
  glBindRenderbuffer(GL_RENDERBUFFER, frameDepth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
  glGenFramebuffers(1, &frameFbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, frameFbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, frameColour_, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, frameIds_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, frameDepth_);
  detail::checkFramebuffer("frame FBO");
  // The passes draw into the colour alone and read the ids: a framebuffer without the id
  // texture, so sampling it is no feedback loop.
  glGenFramebuffers(1, &passFbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, passFbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, frameColour_, 0);
  detail::checkFramebuffer("pass FBO");

  // The room, set up once (spec §3–5), as the Renderer caches its static view.
  const core::Mesh& mesh = view_.staticMesh;
  clip_.resize(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    clip_[i] = raster::transformPoint(view_.cameraViewProj, mesh.positions[i]);
  }
  std::vector<Vertex> vertices;
  staticFirst_.push_back(0);
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t* idx = &mesh.indices[3 * t];
    fan_.clear();
    raster::clipAndSnapTriangle({clip_[idx[0]], clip_[idx[1]], clip_[idx[2]]}, view_.width,
                                view_.height, fan_);
    for (const auto& tri : fan_) {
      SetupTriangle st;
      if (!raster::setupTriangle(tri, view_.width, view_.height, st)) continue;
      staticSubs_.push_back(st);
      emit(st, frameTarget_, static_cast<uint32_t>(t), nullptr, vertices);
    }
    staticFirst_.push_back(static_cast<uint32_t>(staticSubs_.size()));
  }
  staticVertices_ = static_cast<int>(vertices.size());
  glGenVertexArrays(1, &staticVao_);
  glBindVertexArray(staticVao_);
  glGenBuffers(1, &staticBuffer_);
  glBindBuffer(GL_ARRAY_BUFFER, staticBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)),
               vertices.data(), GL_STATIC_DRAW);
  bindVertexLayout();

  glGenVertexArrays(1, &streamVao_);
  glBindVertexArray(streamVao_);
  glGenBuffers(1, &streamBuffer_);
  glBindBuffer(GL_ARRAY_BUFFER, streamBuffer_);
  bindVertexLayout();
  glGenVertexArrays(1, &mapVao_);
  glBindVertexArray(mapVao_);
  glGenBuffers(1, &mapBuffer_);
  glBindBuffer(GL_ARRAY_BUFFER, mapBuffer_);
  bindMapLayout();
  glGenVertexArrays(1, &emptyVao_);
  glBindVertexArray(0);
  GlContext::check("GlTraceReplay setup");
}

GlTraceReplay::~GlTraceReplay() {
  for (ShadowTarget& t : shadowTargets_) {
    glDeleteFramebuffers(1, &t.fbo);
    glDeleteTextures(1, &t.texture);
  }
  const GLuint buffers[] = {staticBuffer_, streamBuffer_, mapBuffer_};
  glDeleteBuffers(3, buffers);
  const GLuint vaos[] = {staticVao_, streamVao_, mapVao_, emptyVao_};
  glDeleteVertexArrays(4, vaos);
  const GLuint fbos[] = {frameFbo_, passFbo_};
  glDeleteFramebuffers(2, fbos);
  glDeleteRenderbuffers(1, &frameDepth_);
  const GLuint textures[] = {frameColour_, frameIds_, backgroundTexture_};
  glDeleteTextures(3, textures);
  for (GLuint p : {mapProgram_, roomProgram_, objectProgram_, passProgram_, backgroundProgram_})
    glDeleteProgram(p);
}

void GlTraceReplay::render(const raster::FrameContent& frame, std::span<uint8_t> rgbaOut) {
  const size_t bytes = static_cast<size_t>(view_.width) * view_.height * 4;
  if (rgbaOut.size() != bytes || frame.background.size() != bytes) {
    throw std::invalid_argument("GlTraceReplay::render: buffer sizes do not match the view");
  }
  if (frame.accumulation != raster::Accumulation::kU8) {
    // GL blending subtracts whole levels per pass (spec §8's u8 rule only).
    throw std::invalid_argument("GlTraceReplay::render: u8 accumulation only");
  }
  for (const raster::ShadowPass& pass : frame.passes) {
    if (pass.penumbraScale > 0) {
      throw std::invalid_argument(
          "GlTraceReplay::render: area-light penumbrae (spec §7) are "
          "not replayed; 2x2 PCF or binary masks only");
    }
  }

  // CPU set-up of this frame's triangles (spec §3–5) into one stream: objects, then per pass
  // its occluder in the light's map, its room receivers and its object receivers.
  stream_.clear();
  mapStream_.clear();
  auto setupMesh = [&](const core::Mesh& mesh, const core::Mat4& m, uint32_t w, uint32_t h,
                       bool cullBackFaces, auto&& each) {
    clip_.resize(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      clip_[i] = raster::transformPoint(m, mesh.positions[i]);
    }
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      const uint32_t* idx = &mesh.indices[3 * t];
      fan_.clear();
      raster::clipAndSnapTriangle({clip_[idx[0]], clip_[idx[1]], clip_[idx[2]]}, w, h, fan_);
      for (const auto& tri : fan_) {
        SetupTriangle st;
        if (cullBackFaces && raster::facesAwayOnMap(tri)) continue;
        if (raster::setupTriangle(tri, w, h, st)) each(t, st);
      }
    }
  };

  // Objects: ids 0x80000000 + g (spec §6 step 3), colour planes (§5); their set-up
  // triangles are kept for the object receivers of the passes.
  std::vector<std::pair<SetupTriangle, uint32_t>> objectSubs;  // (triangle, g)
  uint32_t g0 = 0;
  for (const raster::ShadedMesh& object : frame.objects) {
    setupMesh(object.mesh, view_.cameraViewProj, view_.width, view_.height, false,
              [&](size_t t, const SetupTriangle& st) {
                const uint32_t* idx = &object.mesh.indices[3 * t];
                const core::Rgb8 c0 = object.colours[idx[0]], c1 = object.colours[idx[1]],
                                 c2 = object.colours[idx[2]];
                const AttributePlane planes[3] = {raster::attributePlane(st, {c0.r, c1.r, c2.r}),
                                                  raster::attributePlane(st, {c0.g, c1.g, c2.g}),
                                                  raster::attributePlane(st, {c0.b, c1.b, c2.b})};
                const auto g = g0 + static_cast<uint32_t>(t);
                emit(st, frameTarget_, 0x80000000u + g, planes, stream_);
                objectSubs.emplace_back(st, g);
              });
    g0 += static_cast<uint32_t>(object.mesh.triangleCount());
  }
  const int objectVertices = static_cast<int>(stream_.size());

  struct PassRanges {
    int mapFirst, mapCount, roomFirst, roomCount, objectFirst, objectCount;
  };
  std::vector<PassRanges> ranges(frame.passes.size());
  if (shadowTargets_.size() < frame.passes.size()) shadowTargets_.resize(frame.passes.size());
  auto planesOf = [](const SetupTriangle& st, const core::Rgb16* s, AttributePlane* out) {
    out[0] = raster::attributePlaneFine(st, {s[0].r, s[1].r, s[2].r});
    out[1] = raster::attributePlaneFine(st, {s[0].g, s[1].g, s[2].g});
    out[2] = raster::attributePlaneFine(st, {s[0].b, s[1].b, s[2].b});
  };
  for (size_t p = 0; p < frame.passes.size(); ++p) {
    const raster::ShadowPass& pass = frame.passes[p];
    PassRanges& r = ranges[p];
    ShadowTarget& target = shadowTargets_[p];
    if (target.size != pass.shadowMapSize)
      target.viewport = targetFor(pass.shadowMapSize, pass.shadowMapSize);
    r.mapFirst = static_cast<int>(mapStream_.size());
    setupMesh(frame.occluders[pass.occluder], pass.lightViewProj, pass.shadowMapSize,
              pass.shadowMapSize, pass.cullBackFaces, [&](size_t /*t*/, const SetupTriangle& st) {
                scratch_.clear();
                emit(st, target.viewport, 0, nullptr, scratch_);
                for (const Vertex& v : scratch_) {
                  mapStream_.push_back({v.x, v.y, v.z00, v.dzdx, v.dzdy, v.ox, v.oy});
                }
              });
    r.mapCount = static_cast<int>(mapStream_.size()) - r.mapFirst;
    r.roomFirst = static_cast<int>(stream_.size());
    AttributePlane planes[3];
    for (size_t k = 0; k < pass.receiverTriangles.size(); ++k) {
      const uint32_t t = pass.receiverTriangles[k];
      for (uint32_t sub = staticFirst_[t]; sub < staticFirst_[t + 1]; ++sub) {
        planesOf(staticSubs_[sub], &pass.receiverS[3 * k], planes);
        emit(staticSubs_[sub], frameTarget_, t, planes, stream_);
      }
    }
    r.roomCount = static_cast<int>(stream_.size()) - r.roomFirst;
    r.objectFirst = static_cast<int>(stream_.size());
    for (size_t k = 0; k < pass.objectTriangles.size(); ++k) {
      const uint32_t g = pass.objectTriangles[k];
      for (const auto& [st, owner] : objectSubs) {
        if (owner != g) continue;
        planesOf(st, &pass.objectS[3 * k], planes);
        emit(st, frameTarget_, 0x80000000u + g, planes, stream_);
      }
    }
    r.objectCount = static_cast<int>(stream_.size()) - r.objectFirst;
  }
  glBindBuffer(GL_ARRAY_BUFFER, streamBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(stream_.size() * sizeof(Vertex)),
               stream_.data(), GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, mapBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mapStream_.size() * sizeof(MapVertex)),
               mapStream_.data(), GL_STREAM_DRAW);

  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);  // both windings are drawn (spec §4)
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glClearDepthf(1.0f);  // z / 2 <= 0.5 for every drawn z: 1.0 is the spec's +inf

  // Spec §6 step 1: every pass's map, z < depth in triangle order (GL_LESS on z / 2).
  glUseProgram(mapProgram_);
  glBindVertexArray(mapVao_);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  for (size_t p = 0; p < frame.passes.size(); ++p) {
    const raster::ShadowPass& pass = frame.passes[p];
    ShadowTarget& target = shadowTargets_[p];
    const auto size = static_cast<GLsizei>(pass.shadowMapSize);
    if (target.size != pass.shadowMapSize) {
      if (target.texture != 0) {
        glDeleteFramebuffers(1, &target.fbo);
        glDeleteTextures(1, &target.texture);
      }
      glGenTextures(1, &target.texture);
      glBindTexture(GL_TEXTURE_2D, target.texture);
      glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, size, size);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glGenFramebuffers(1, &target.fbo);
      glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, target.texture, 0);
      const GLenum none = GL_NONE;
      glDrawBuffers(1, &none);
      glReadBuffer(GL_NONE);
      detail::checkFramebuffer("shadow map FBO");
      target.size = pass.shadowMapSize;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glClear(GL_DEPTH_BUFFER_BIT);
    setViewport(target.viewport.side, target.viewport.origin);
    glDrawArrays(GL_TRIANGLES, ranges[p].mapFirst, ranges[p].mapCount);
  }

  // Background, ids cleared to kNoSurface, depth to +inf.
  const auto w = static_cast<GLsizei>(view_.width), h = static_cast<GLsizei>(view_.height);
  glBindFramebuffer(GL_FRAMEBUFFER, frameFbo_);
  const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  const GLenum colourOnly[] = {GL_COLOR_ATTACHMENT0, GL_NONE};
  const GLenum idOnly[] = {GL_NONE, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, both);
  const GLuint noSurface[4] = {0xFFFFFFFEu, 0, 0, 0};
  glClearBufferuiv(GL_COLOR, 1, noSurface);
  glClear(GL_DEPTH_BUFFER_BIT);
  glBindTexture(GL_TEXTURE_2D, backgroundTexture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Row 0 (our top) is texture row 0 = GL window row 0: the snapped Y is used directly.
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, frame.background.data());
  glDisable(GL_DEPTH_TEST);
  glDrawBuffers(2, colourOnly);
  glViewport(0, 0, w, h);
  glUseProgram(backgroundProgram_);
  glActiveTexture(GL_TEXTURE0);
  glUniform1i(glGetUniformLocation(backgroundProgram_, "background"), 0);
  glBindVertexArray(emptyVao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  // Step 2: the room into depth and ids; step 3: objects into depth, ids and colour.
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  setViewport(frameTarget_.side, frameTarget_.origin);
  glUseProgram(roomProgram_);
  glDrawBuffers(2, idOnly);
  glBindVertexArray(staticVao_);
  glDrawArrays(GL_TRIANGLES, 0, staticVertices_);
  glUseProgram(objectProgram_);
  glDrawBuffers(2, both);
  glBindVertexArray(streamVao_);
  glDrawArrays(GL_TRIANGLES, 0, objectVertices);

  // Step 4: receivers where the id is their own, dst = max(dst - round(S M / 255), 0) per
  // colour channel, alpha untouched.
  if (!frame.passes.empty()) {
    glDisable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, passFbo_);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_REVERSE_SUBTRACT);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(passProgram_);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, frameIds_);
    glUniform1i(glGetUniformLocation(passProgram_, "ids"), 1);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(passProgram_, "shadowMap"), 0);
    const GLint rows[4] = {
        glGetUniformLocation(passProgram_, "p0"), glGetUniformLocation(passProgram_, "p1"),
        glGetUniformLocation(passProgram_, "p2"), glGetUniformLocation(passProgram_, "p3")};
    const GLint mapSize = glGetUniformLocation(passProgram_, "mapSize");
    const GLint bias = glGetUniformLocation(passProgram_, "depthBias");
    const GLint pcf = glGetUniformLocation(passProgram_, "pcf2x2");
    for (size_t p = 0; p < frame.passes.size(); ++p) {
      const raster::ShadowPass& pass = frame.passes[p];
      const core::Mat4 toTexel = windowToLightTexel(view_.cameraViewProj, view_.width, view_.height,
                                                    pass.lightViewProj, pass.shadowMapSize);
      for (size_t r = 0; r < 4; ++r) glUniform4fv(rows[r], 1, &toTexel.m[4 * r]);
      glUniform1i(mapSize, static_cast<GLint>(pass.shadowMapSize));
      glUniform1i(pcf, pass.pcf2x2 ? 1 : 0);
      glBindTexture(GL_TEXTURE_2D, shadowTargets_[p].texture);
      glUniform1f(bias, pass.depthBias);
      glDrawArrays(GL_TRIANGLES, ranges[p].roomFirst, ranges[p].roomCount);
      if (ranges[p].objectCount > 0) {
        glUniform1f(bias, pass.objectDepthBias);
        glDrawArrays(GL_TRIANGLES, ranges[p].objectFirst, ranges[p].objectCount);
      }
    }
    glDisable(GL_BLEND);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }

  glFinish();
  glBindFramebuffer(GL_FRAMEBUFFER, passFbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  // GL row r is our row r (snapped Y used as GL window y): no reversal needed.
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgbaOut.data());
  GlContext::check("GlTraceReplay::render");
}

}  // namespace penumbra::gl
