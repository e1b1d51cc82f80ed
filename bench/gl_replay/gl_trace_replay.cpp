#include "bench/gl_replay/gl_trace_replay.h"

#include <GLES3/gl3.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "bench/gl_replay/gl_context.h"
#include "bench/gl_replay/gl_util.h"

namespace penumbra::gl {
namespace {

using core::Mat4;
using Mat4d = std::array<double, 16>;

// One vertex shader for every geometry draw (static depth, objects, receivers, shadow
// maps): the same source, the same uniform and the same input floats give the same
// gl_Position in every program (`invariant`), so the receiver draws hit GL_EQUAL against
// the depth the static draw wrote. Negating y puts GL's window row r on our row r.
const char* const kGeometryVertex = R"(#version 300 es
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 value;  // 0..255: object colour or intensity transfer S
uniform mat4 viewProj;
invariant gl_Position;
out vec3 attributeW;
out float clipW;
void main() {
  vec4 clip = viewProj * vec4(position, 1.0);
  gl_Position = vec4(clip.x, -clip.y, clip.z, clip.w);
  attributeW = value * clip.w;
  clipW = clip.w;
}
)";

const char* const kDepthOnlyFragment = R"(#version 300 es
void main() {}
)";

const char* const kObjectFragment = R"(#version 300 es
precision highp float;
in vec3 attributeW;
in float clipW;
out vec4 colour;
void main() { colour = vec4((attributeW / clipW) / 255.0, 1.0); }
)";

// Spec §6 step 4 and §7: q = P (sx, sy, z, 1) from the fragment's window position and its
// depth (equal to the depth buffer's, GL_EQUAL), projective divide, compare with the bias,
// output S*M/255 for the reverse-subtract blend. The map has a one-texel ring of depth 1
// around the size x size interior, so lookups outside the map never occlude (spec §7)
// without GL_CLAMP_TO_BORDER (not in ES 3.0).
const char* const kPassFragment = R"(#version 300 es
precision highp float;
precision highp sampler2DShadow;
uniform highp sampler2DShadow shadowMap;
uniform mat4 windowToTexel;
uniform float invTextureSide;
uniform float depthBias;
in vec3 attributeW;
in float clipW;
out vec4 colour;
void main() {
  vec3 s = attributeW / clipW;
  vec4 q = windowToTexel * vec4(gl_FragCoord.xyz, 1.0);
  float m = 0.0;
  if (q.w > 0.0) {
    vec3 t = q.xyz / q.w;
    m = texture(shadowMap, vec3((t.x + 1.0) * invTextureSide, (t.y + 1.0) * invTextureSide,
                                t.z - depthBias));
  }
  colour = vec4(s * (m / 255.0), 0.0);
}
)";

const char* const kBackgroundVertex = R"(#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID >> 1) * 4 - 1));
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

const char* const kBackgroundFragment = R"(#version 300 es
precision highp float;
uniform highp sampler2D background;
out vec4 colour;
void main() { colour = texelFetch(background, ivec2(gl_FragCoord.xy), 0); }
)";

Mat4d toDouble(const core::Mat4& m) {
  Mat4d d{};
  for (size_t i = 0; i < 16; ++i) d[i] = m.m[i];
  return d;
}

Mat4d multiply(const Mat4d& a, const Mat4d& b) {
  Mat4d r{};
  for (size_t i = 0; i < 4; ++i) {
    for (size_t j = 0; j < 4; ++j) {
      double s = 0;
      for (size_t k = 0; k < 4; ++k) s += a[4 * i + k] * b[4 * k + j];
      r[4 * i + j] = s;
    }
  }
  return r;
}

// Gauss-Jordan with partial pivoting, binary64. (Our renderer uses a cofactor expansion,
// spec §7; the two agree to far below binary32 rounding for sane cameras.)
Mat4d inverse(const Mat4d& m) {
  Mat4d a = m;
  Mat4d inv{};
  for (size_t i = 0; i < 4; ++i) inv[5 * i] = 1.0;
  for (size_t col = 0; col < 4; ++col) {
    size_t pivot = col;
    for (size_t r = col + 1; r < 4; ++r) {
      if (std::fabs(a[4 * r + col]) > std::fabs(a[4 * pivot + col])) pivot = r;
    }
    if (a[4 * pivot + col] == 0.0) throw std::invalid_argument("singular camera matrix");
    for (size_t k = 0; k < 4; ++k) {
      std::swap(a[4 * col + k], a[4 * pivot + k]);
      std::swap(inv[4 * col + k], inv[4 * pivot + k]);
    }
    const double p = a[4 * col + col];
    for (size_t k = 0; k < 4; ++k) {
      a[4 * col + k] /= p;
      inv[4 * col + k] /= p;
    }
    for (size_t r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double f = a[4 * r + col];
      if (f == 0.0) continue;
      for (size_t k = 0; k < 4; ++k) {
        a[4 * r + k] -= f * a[4 * col + k];
        inv[4 * r + k] -= f * inv[4 * col + k];
      }
    }
  }
  return inv;
}

void uploadMatrix(GLuint program, const char* name, const core::Mat4& m) {
  // Our matrices are row-major; GL_TRUE transposes them into GL's column-major storage.
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_TRUE, m.m.data());
}

}  // namespace

core::Mat4 windowToLightTexel(const core::Mat4& camera, uint32_t width, uint32_t height,
                              const core::Mat4& light, uint32_t shadowMapSize) {
  const double hw = width / 2.0, hh = height / 2.0, s = shadowMapSize / 2.0;
  const Mat4d windowToNdc = {1.0 / hw, 0,         0, -1,  //
                             0,        -1.0 / hh, 0, 1,   //
                             0,        0,         2, -1,  //
                             0,        0,         0, 1};
  const Mat4d ndcToTexel = {s, 0,  0,   s,    //
                            0, -s, 0,   s,    //
                            0, 0,  0.5, 0.5,  //
                            0, 0,  0,   1};
  const Mat4d p = multiply(
      multiply(multiply(ndcToTexel, toDouble(light)), inverse(toDouble(camera))), windowToNdc);
  core::Mat4 out;
  for (size_t i = 0; i < 16; ++i) out.m[i] = static_cast<float>(p[i]);
  return out;
}

GlTraceReplay::GlTraceReplay(const raster::StaticView& view) : view_(view) {
  geometryProgram_ = detail::buildProgram(kGeometryVertex, kObjectFragment, "objects");
  depthProgram_ = detail::buildProgram(kGeometryVertex, kDepthOnlyFragment, "depth only");
  passProgram_ = detail::buildProgram(kGeometryVertex, kPassFragment, "mask and subtract");
  backgroundProgram_ = detail::buildProgram(kBackgroundVertex, kBackgroundFragment, "background");

  const auto w = static_cast<GLsizei>(view_.width), h = static_cast<GLsizei>(view_.height);
  glGenTextures(1, &frameColour_);
  glBindTexture(GL_TEXTURE_2D, frameColour_);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
  glGenRenderbuffers(1, &frameDepth_);
  glBindRenderbuffer(GL_RENDERBUFFER, frameDepth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
  glGenFramebuffers(1, &frameFbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, frameFbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, frameColour_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, frameDepth_);
  detail::checkFramebuffer("frame FBO");

  glGenTextures(1, &backgroundTexture_);
  glBindTexture(GL_TEXTURE_2D, backgroundTexture_);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

  // Static mesh: positions and indices stay in GL buffers across frames.
  const core::Mesh& mesh = view_.staticMesh;
  glGenVertexArrays(1, &staticVao_);
  glBindVertexArray(staticVao_);
  glGenBuffers(1, &staticPositions_);
  glBindBuffer(GL_ARRAY_BUFFER, staticPositions_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.positions.size() * sizeof(core::Vec3)),
               mesh.positions.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(core::Vec3), nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &staticIndices_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, staticIndices_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(),
               GL_STATIC_DRAW);

  glGenVertexArrays(1, &streamVao_);
  glBindVertexArray(streamVao_);
  glGenBuffers(1, &streamPositions_);
  glBindBuffer(GL_ARRAY_BUFFER, streamPositions_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &streamAttributes_);
  glBindBuffer(GL_ARRAY_BUFFER, streamAttributes_);
  // Unnormalised unsigned bytes arrive as floats 0..255.
  glVertexAttribPointer(1, 3, GL_UNSIGNED_BYTE, GL_FALSE, 3, nullptr);
  glEnableVertexAttribArray(1);

  glGenVertexArrays(1, &emptyVao_);
  glBindVertexArray(0);
  GlContext::check("GlTraceReplay setup");
}

GlTraceReplay::~GlTraceReplay() {
  for (ShadowTarget& t : shadowTargets_) {
    glDeleteFramebuffers(1, &t.fbo);
    glDeleteTextures(1, &t.texture);
  }
  const GLuint buffers[] = {staticPositions_, staticIndices_, streamPositions_, streamAttributes_};
  glDeleteBuffers(4, buffers);
  const GLuint vaos[] = {staticVao_, streamVao_, emptyVao_};
  glDeleteVertexArrays(3, vaos);
  glDeleteFramebuffers(1, &frameFbo_);
  glDeleteRenderbuffers(1, &frameDepth_);
  const GLuint textures[] = {frameColour_, backgroundTexture_};
  glDeleteTextures(2, textures);
  for (GLuint p : {geometryProgram_, depthProgram_, passProgram_, backgroundProgram_}) {
    glDeleteProgram(p);
  }
}

void GlTraceReplay::drawShadowMap(const raster::ShadowPass& pass, const core::Mesh& occluder,
                                  ShadowTarget& target, int firstVertex) {
  const auto side = static_cast<GLsizei>(pass.shadowMapSize + 2);
  if (target.size != pass.shadowMapSize) {
    if (target.texture != 0) {
      glDeleteFramebuffers(1, &target.fbo);
      glDeleteTextures(1, &target.texture);
    }
    glGenTextures(1, &target.texture);
    glBindTexture(GL_TEXTURE_2D, target.texture);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, side, side);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    // Occludes when d - bias > map (spec §7: d > map + bias).
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_GREATER);
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
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glClearDepthf(1.0f);
  glClear(GL_DEPTH_BUFFER_BIT);
  // The interior starts at texel (1, 1); integer offsets keep the snap of spec §2.
  const auto size = static_cast<GLsizei>(pass.shadowMapSize);
  glViewport(1, 1, size, size);
  glScissor(1, 1, size, size);
  glEnable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(depthProgram_);
  uploadMatrix(depthProgram_, "viewProj", pass.lightViewProj);
  glBindVertexArray(streamVao_);
  glDrawArrays(GL_TRIANGLES, firstVertex, static_cast<GLsizei>(occluder.indices.size()));
  glDisable(GL_SCISSOR_TEST);
}

void GlTraceReplay::render(const raster::FrameContent& frame, std::span<uint8_t> rgbaOut) {
  const size_t bytes = static_cast<size_t>(view_.width) * view_.height * 4;
  if (rgbaOut.size() != bytes || frame.background.size() != bytes) {
    throw std::invalid_argument("GlTraceReplay::render: buffer sizes do not match the view");
  }
  const core::Mesh& staticMesh = view_.staticMesh;

  // De-index this frame's geometry into one stream: objects, occluders, receivers.
  positions_.clear();
  attributes_.clear();
  auto push = [&](const core::Vec3& p, const core::Rgb8& a) {
    positions_.insert(positions_.end(), {p.x, p.y, p.z});
    attributes_.insert(attributes_.end(), {a.r, a.g, a.b});
  };
  std::vector<std::pair<int, int>> objectRanges, occluderRanges, passRanges;
  auto vertexCount = [&] { return static_cast<int>(positions_.size() / 3); };
  for (const raster::ShadedMesh& object : frame.objects) {
    const int first = vertexCount();
    for (uint32_t i : object.mesh.indices) push(object.mesh.positions[i], object.colours[i]);
    objectRanges.emplace_back(first, vertexCount() - first);
  }
  for (const core::Mesh& occluder : frame.occluders) {
    const int first = vertexCount();
    for (uint32_t i : occluder.indices) push(occluder.positions[i], core::Rgb8{});
    occluderRanges.emplace_back(first, vertexCount() - first);
  }
  for (const raster::ShadowPass& pass : frame.passes) {
    const int first = vertexCount();
    for (size_t t = 0; t < pass.receiverTriangles.size(); ++t) {
      const size_t tri = pass.receiverTriangles[t];
      for (size_t k = 0; k < 3; ++k) {
        // GL blends in 8 bits: S in whole levels (traces replayed here have u8 accumulation,
        // whose S are whole levels; a fraction would be rounded per pixel, not per vertex).
        const core::Rgb16 s = pass.receiverS[3 * t + k];
        push(staticMesh.positions[staticMesh.indices[3 * tri + k]],
             core::Rgb8{static_cast<uint8_t>((s.r + 128) >> 8),
                        static_cast<uint8_t>((s.g + 128) >> 8),
                        static_cast<uint8_t>((s.b + 128) >> 8)});
      }
    }
    passRanges.emplace_back(first, vertexCount() - first);
  }
  glBindBuffer(GL_ARRAY_BUFFER, streamPositions_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(positions_.size() * sizeof(float)),
               positions_.data(), GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, streamAttributes_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(attributes_.size()), attributes_.data(),
               GL_STREAM_DRAW);

  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);  // both windings are drawn (spec §4)
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);

  // Spec §6 step 1: every pass's shadow map before the frame.
  if (shadowTargets_.size() < frame.passes.size()) shadowTargets_.resize(frame.passes.size());
  for (size_t p = 0; p < frame.passes.size(); ++p) {
    const raster::ShadowPass& pass = frame.passes[p];
    drawShadowMap(pass, frame.occluders[pass.occluder], shadowTargets_[p],
                  occluderRanges[pass.occluder].first);
  }

  const auto w = static_cast<GLsizei>(view_.width), h = static_cast<GLsizei>(view_.height);
  glBindFramebuffer(GL_FRAMEBUFFER, frameFbo_);
  glViewport(0, 0, w, h);
  glDepthMask(GL_TRUE);
  glClearDepthf(1.0f);
  glClear(GL_DEPTH_BUFFER_BIT);

  // Background: uploaded with row 0 (our top) as texture row 0 = GL window row 0.
  glBindTexture(GL_TEXTURE_2D, backgroundTexture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, frame.background.data());
  glDisable(GL_DEPTH_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glUseProgram(backgroundProgram_);
  glActiveTexture(GL_TEXTURE0);
  glUniform1i(glGetUniformLocation(backgroundProgram_, "background"), 0);
  glBindVertexArray(emptyVao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  // Step 2: static mesh into depth only (z < depth).
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glUseProgram(depthProgram_);
  uploadMatrix(depthProgram_, "viewProj", view_.cameraViewProj);
  glBindVertexArray(staticVao_);
  glVertexAttrib3f(1, 0.0f, 0.0f, 0.0f);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(staticMesh.indices.size()), GL_UNSIGNED_INT,
                 nullptr);

  // Step 3: objects, colour and depth (z < depth).
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glUseProgram(geometryProgram_);
  uploadMatrix(geometryProgram_, "viewProj", view_.cameraViewProj);
  glBindVertexArray(streamVao_);
  for (const auto& [first, count] : objectRanges) glDrawArrays(GL_TRIANGLES, first, count);

  // Step 4: receivers where their own depth survived (GL_EQUAL stands in for the id
  // test), dst = max(dst - S*M/255, 0) per colour channel, alpha untouched.
  if (!frame.passes.empty()) {
    glDepthFunc(GL_EQUAL);
    glDepthMask(GL_FALSE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_REVERSE_SUBTRACT);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(passProgram_);
    uploadMatrix(passProgram_, "viewProj", view_.cameraViewProj);
    glUniform1i(glGetUniformLocation(passProgram_, "shadowMap"), 0);
    const GLint windowToTexel = glGetUniformLocation(passProgram_, "windowToTexel");
    const GLint invSide = glGetUniformLocation(passProgram_, "invTextureSide");
    const GLint bias = glGetUniformLocation(passProgram_, "depthBias");
    for (size_t p = 0; p < frame.passes.size(); ++p) {
      const raster::ShadowPass& pass = frame.passes[p];
      const core::Mat4 toTexel = windowToLightTexel(view_.cameraViewProj, view_.width, view_.height,
                                                    pass.lightViewProj, pass.shadowMapSize);
      glUniformMatrix4fv(windowToTexel, 1, GL_TRUE, toTexel.m.data());
      glUniform1f(invSide, 1.0f / static_cast<float>(pass.shadowMapSize + 2));
      glUniform1f(bias, pass.depthBias);
      glBindTexture(GL_TEXTURE_2D, shadowTargets_[p].texture);
      // 2x2 PCF is GL's bilinear filter of the four comparisons (spec §7).
      const GLint filter = pass.pcf2x2 ? GL_LINEAR : GL_NEAREST;
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
      glDrawArrays(GL_TRIANGLES, passRanges[p].first, passRanges[p].second);
    }
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }

  glFinish();
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  // GL row r is our row r (y negated in the vertex shader): no reversal needed.
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgbaOut.data());
  GlContext::check("GlTraceReplay::render");
}

}  // namespace penumbra::gl
