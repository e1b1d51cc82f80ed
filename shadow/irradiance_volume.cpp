#include "shadow/irradiance_volume.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::shadow {

void IrradianceVolume::validate() const {
  if (dims.x < 1 || dims.y < 1 || dims.z < 1) {
    throw std::invalid_argument("irradiance volume: dims must be at least 1");
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(origin[a]) || !std::isfinite(spacing[a]) || !(spacing[a] > 0)) {
      throw std::invalid_argument("irradiance volume: origin/spacing not finite and positive");
    }
  }
  const size_t n = vertexCount();
  if (coefficients.size() != n * kShFloats) {
    throw std::invalid_argument("irradiance volume: " + std::to_string(coefficients.size()) +
                                " coefficients, expected " + std::to_string(n * kShFloats));
  }
  if (valid.size() != n) {
    throw std::invalid_argument("irradiance volume: one validity flag per vertex expected");
  }
  for (float c : coefficients) {
    if (!std::isfinite(c)) throw std::invalid_argument("irradiance volume: non-finite coefficient");
  }
  for (float c : fallback) {
    if (!std::isfinite(c)) throw std::invalid_argument("irradiance volume: non-finite fallback");
  }
}

glm::vec3 IrradianceVolume::irradianceOverPi(const glm::vec3& p, const glm::vec3& n) const {
  float basis[kShCoefficients];
  shBasis9(n.x, n.y, n.z, basis);

  // Grid coordinates, clamped to the lattice; cell (i0, i0 + 1) per axis.
  int i0[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    const int d = static_cast<int>(dims[a]);
    float g = (p[a] - origin[a]) / spacing[a];
    if (!(g > 0.0f)) g = 0.0f;  // also NaN → 0
    if (g > float(d - 1)) g = float(d - 1);
    int i = static_cast<int>(g);  // g >= 0: truncation is floor
    if (i > d - 2) i = d - 2 < 0 ? 0 : d - 2;
    i0[a] = i;
    f[a] = g - float(i);
  }
  // Corners in a fixed order (x fastest); each corner's E/pi dotted first, then blended.
  float sum[3] = {0.0f, 0.0f, 0.0f};
  float weightSum = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    int idx[3];
    float w = 1.0f;
    bool outside = false;
    for (int a = 0; a < 3; ++a) {
      const int hi = (corner >> a) & 1;
      idx[a] = i0[a] + hi;
      if (idx[a] >= static_cast<int>(dims[a])) {
        outside = true;  // a one-vertex axis: only its lower corner exists
        break;
      }
      w = w * (hi ? f[a] : 1.0f - f[a]);
    }
    if (outside) continue;
    const size_t v = (size_t(idx[2]) * dims.y + size_t(idx[1])) * dims.x + size_t(idx[0]);
    if (!valid[v] || w == 0.0f) continue;
    const float* c = &coefficients[v * kShFloats];
    for (int ch = 0; ch < 3; ++ch) {
      float e = 0.0f;
      for (int k = 0; k < kShCoefficients; ++k) e = e + basis[k] * c[k * 3 + ch];
      sum[ch] = sum[ch] + w * e;
    }
    weightSum = weightSum + w;
  }
  glm::vec3 out;
  if (weightSum > 0.0f) {
    for (int ch = 0; ch < 3; ++ch) out[ch] = sum[ch] / weightSum;
  } else {
    for (int ch = 0; ch < 3; ++ch) {
      float e = 0.0f;
      for (int k = 0; k < kShCoefficients; ++k) e = e + basis[k] * fallback[size_t(k * 3 + ch)];
      out[ch] = e;
    }
  }
  // The order-2 reconstruction rings slightly negative behind strong lights.
  for (int ch = 0; ch < 3; ++ch) out[ch] = out[ch] > 0.0f ? out[ch] : 0.0f;
  return out;
}

void shadeVerticesDiffuse(const IrradianceVolume& volume, std::span<const raster::Vec3> positions,
                          std::span<const glm::vec3> normals, const glm::vec3& reflectance,
                          const ToneCurve& tone, std::span<raster::Rgb8> colours,
                          std::span<glm::vec3> radiance) {
  if (normals.size() != positions.size() || colours.size() != positions.size() ||
      (!radiance.empty() && radiance.size() != positions.size())) {
    throw std::invalid_argument("shadeVerticesDiffuse: span sizes differ");
  }
  for (size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3& m = normals[v];
    const float length = std::sqrt(m.x * m.x + m.y * m.y + m.z * m.z);  // sqrt is IEEE-exact
    const glm::vec3 n = length > 0.0f ? glm::vec3(m.x / length, m.y / length, m.z / length)
                                      : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 e =
        volume.irradianceOverPi(glm::vec3(positions[v].x, positions[v].y, positions[v].z), n);
    const glm::vec3 l(reflectance.x * e.x, reflectance.y * e.y, reflectance.z * e.z);
    if (!radiance.empty()) radiance[v] = l;
    colours[v] = tone.map(glm::dvec3(l));
  }
}

std::vector<glm::vec3> vertexNormals(const raster::Mesh& m) {
  std::vector<glm::vec3> normals(m.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    const raster::Vec3 &a = m.positions[m.indices[3 * t]], &b = m.positions[m.indices[3 * t + 1]],
                       &c = m.positions[m.indices[3 * t + 2]];
    const glm::vec3 u(b.x - a.x, b.y - a.y, b.z - a.z), w(c.x - a.x, c.y - a.y, c.z - a.z);
    const glm::vec3 n(u.y * w.z - u.z * w.y, u.z * w.x - u.x * w.z, u.x * w.y - u.y * w.x);
    for (int k = 0; k < 3; ++k) {
      glm::vec3& s = normals[m.indices[3 * t + size_t(k)]];
      s = glm::vec3(s.x + n.x, s.y + n.y, s.z + n.z);
    }
  }
  return normals;
}

}  // namespace penumbra::shadow
