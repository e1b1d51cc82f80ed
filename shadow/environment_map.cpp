#include "shadow/environment_map.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "raster/renderer.h"
#include "scene/camera.h"

namespace penumbra::shadow {
namespace {

struct Face {
  glm::vec3 forward, up, right;  // right = forward x up
};
// +x, -x, +y, -y, +z, -z; each face's camera looks along `forward` with `up` on top.
constexpr std::array<Face, 6> kFaces = {{
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
    {{-1, 0, 0}, {0, 1, 0}, {0, 0, -1}},
    {{0, 1, 0}, {0, 0, -1}, {1, 0, 0}},
    {{0, -1, 0}, {0, 0, 1}, {1, 0, 0}},
    {{0, 0, 1}, {0, 1, 0}, {-1, 0, 0}},
    {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
}};

float dot3(const glm::vec3& a, const glm::vec3& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}

glm::vec3 normalized(const glm::vec3& v) {
  const float l = std::sqrt(dot3(v, v));
  const float inv = 1.0f / l;
  return {v.x * inv, v.y * inv, v.z * inv};
}

glm::vec3 cross3(const glm::vec3& a, const glm::vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

}  // namespace

double powInt(double c, uint32_t k) {
  double r = 1, b = c;
  while (k) {
    if (k & 1) r *= b;
    b *= b;
    k >>= 1;
  }
  return r;
}

glm::vec3 CubeEnvironmentMap::lookup(const glm::vec3& d, const ToneInverse& inverse) const {
  // Major axis → face; then the face camera's normalized device coordinates.
  const float ax = d.x < 0 ? -d.x : d.x, ay = d.y < 0 ? -d.y : d.y, az = d.z < 0 ? -d.z : d.z;
  int face;
  if (ax >= ay && ax >= az) {
    face = d.x >= 0 ? 0 : 1;
  } else if (ay >= az) {
    face = d.y >= 0 ? 2 : 3;
  } else {
    face = d.z >= 0 ? 4 : 5;
  }
  const Face& f = kFaces[size_t(face)];
  const float depth = dot3(d, f.forward);
  if (!(depth > 0.0f)) return glm::vec3(0.0f);  // zero or NaN direction
  const float x = dot3(d, f.right) / depth, y = dot3(d, f.up) / depth;
  const float fs = float(size);
  float col = (x + 1.0f) * 0.5f * fs, row = (1.0f - y) * 0.5f * fs;
  col = col < 0.0f ? 0.0f : (col > fs - 1.0f ? fs - 1.0f : col);
  row = row < 0.0f ? 0.0f : (row > fs - 1.0f ? fs - 1.0f : row);
  const size_t texel =
      (size_t(face) * size * size + size_t(row) * size + size_t(col)) * 4;  // truncation: floor
  return {inverse(rgba[texel]), inverse(rgba[texel + 1]), inverse(rgba[texel + 2])};
}

raster::ShadedMesh roomForEnvironment(const core::Mesh& mesh,
                                      std::span<const uint32_t> trianglePatch,
                                      std::span<const glm::vec3> patchRadiance,
                                      const ToneCurve& tone) {
  if (trianglePatch.size() != mesh.triangleCount()) {
    throw std::invalid_argument("roomForEnvironment: one patch per triangle expected");
  }
  std::vector<glm::dvec3> sum(mesh.positions.size(), glm::dvec3(0.0));
  std::vector<uint32_t> count(mesh.positions.size(), 0);
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (trianglePatch[t] >= patchRadiance.size()) {
      throw std::invalid_argument("roomForEnvironment: patch index out of range");
    }
    const glm::dvec3 l(patchRadiance[trianglePatch[t]]);
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = mesh.indices[3 * t + size_t(c)];
      sum[v] += l;
      ++count[v];
    }
  }
  raster::ShadedMesh room;
  room.mesh = mesh;
  room.colours.resize(mesh.positions.size());
  for (size_t v = 0; v < sum.size(); ++v) {
    room.colours[v] = count[v] ? tone.map(sum[v] / double(count[v])) : core::Rgb8{};
  }
  return room;
}

void renderEnvironmentMap(const raster::ShadedMesh& room, const glm::vec3& centre, uint32_t size,
                          float farDistance, CubeEnvironmentMap& out) {
  if (size < 4 || size > 512) throw std::invalid_argument("environment map size not in 4..512");
  out.size = size;
  out.centre = centre;
  out.rgba.resize(size_t{6} * size * size * 4);
  const size_t faceBytes = size_t{size} * size * 4;
  raster::FrameContent frame;
  frame.background.assign(faceBytes, 0);
  for (size_t i = 3; i < faceBytes; i += 4) frame.background[i] = 255;
  frame.objects.push_back(room);
  const glm::dmat4 projection =
      scene::perspectiveFromTanHalf(1.0, 1.0, 0.01, std::max(double(farDistance), 0.02));
  const glm::dvec3 eye(centre);
  for (size_t f = 0; f < 6; ++f) {
    const glm::dmat4 view =
        scene::lookAt(eye, eye + glm::dvec3(kFaces[f].forward), glm::dvec3(kFaces[f].up));
    const raster::StaticView v{size, size, scene::toRasterMat4(projection * view), {}};
    raster::Renderer renderer(v, {simd::Isa::kScalar, 1, 16});
    renderer.render(frame, std::span(out.rgba).subspan(f * faceBytes, faceBytes));
  }
}

PhongLobe::PhongLobe(float exponent) {
  const double e = exponent > 0 && std::isfinite(exponent) ? double(exponent) : 0.0;
  const uint32_t n = static_cast<uint32_t>(e < 1e6 ? e + 0.5 : 1e6);  // rounded
  roundedExponent = n;
  for (int k = 0; k < kLobeRings; ++k) {
    // The lobe's energy below polar cosine c is 1 - c^(n + 1): ring k sits at the middle
    // quantile (k + 0.5) / kLobeRings, i.e. c^(n + 1) = 1 - (k + 0.5) / kLobeRings.
    const double target = 1.0 - (k + 0.5) / kLobeRings;
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 40; ++it) {
      const double mid = 0.5 * (lo + hi);
      (powInt(mid, n + 1) < target ? lo : hi) = mid;
    }
    const double c = 0.5 * (lo + hi);
    cosTheta[size_t(k)] = static_cast<float>(c);
    sinTheta[size_t(k)] = static_cast<float>(std::sqrt(1.0 - c * c));
  }
}

glm::vec3 specularRadiance(const CubeEnvironmentMap& map, const ToneInverse& inverse,
                           const PhongLobe& lobe, const glm::vec3& position,
                           const glm::vec3& normal, const glm::vec3& eye) {
  const float nl = dot3(normal, normal);
  const glm::vec3 toEye = eye - position;
  const float el = dot3(toEye, toEye);
  if (!(nl > 0.0f) || !(el > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 n = normalized(normal), v = normalized(toEye);
  const float nv = dot3(n, v);
  // r = 2 (n.v) n - v: the mirror direction.
  const glm::vec3 r(2.0f * nv * n.x - v.x, 2.0f * nv * n.y - v.y, 2.0f * nv * n.z - v.z);
  // A frame around r: t1 from the axis least aligned with it.
  const float ax = r.x < 0 ? -r.x : r.x, ay = r.y < 0 ? -r.y : r.y, az = r.z < 0 ? -r.z : r.z;
  const glm::vec3 axis = ax <= ay && ax <= az ? glm::vec3(1, 0, 0)
                         : ay <= az           ? glm::vec3(0, 1, 0)
                                              : glm::vec3(0, 0, 1);
  const glm::vec3 t1 = normalized(cross3(r, axis));
  const glm::vec3 t2 = cross3(r, t1);
  // Azimuths 45 degrees apart: (cos, sin) from exact constants and sqrt(0.5).
  const float h = std::sqrt(0.5f);
  const float cs[kLobeAzimuths][2] = {{1, 0},  {h, h},   {0, 1},  {-h, h},
                                      {-1, 0}, {-h, -h}, {0, -1}, {h, -h}};
  glm::vec3 sum(0.0f);
  for (int k = 0; k < kLobeRings; ++k) {
    const float c = lobe.cosTheta[size_t(k)], s = lobe.sinTheta[size_t(k)];
    for (int a = 0; a < kLobeAzimuths; ++a) {
      const float u = s * cs[a][0], w = s * cs[a][1];
      const glm::vec3 d((c * r.x + u * t1.x) + w * t2.x, (c * r.y + u * t1.y) + w * t2.y,
                        (c * r.z + u * t1.z) + w * t2.z);
      const glm::vec3 l = map.lookup(d, inverse);
      sum = glm::vec3(sum.x + l.x, sum.y + l.y, sum.z + l.z);
    }
  }
  const float inv = 1.0f / float(kLobeRings * kLobeAzimuths);
  return {sum.x * inv, sum.y * inv, sum.z * inv};
}

}  // namespace penumbra::shadow
