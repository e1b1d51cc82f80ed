#include "shadow/irradiance_volume.h"

#include <bit>
#include <cmath>
#include <cstring>
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
  // Corner weights in a fixed order (x fastest); invalid or missing corners weigh 0 and
  // read a zero record, so the blend below has no branches.
  static constexpr std::array<float, kShFloats> kZero{};
  // Per axis: the lower and upper weights, and whether the upper vertex exists (a
  // one-vertex axis has none). A corner's weight is (w_x w_y) w_z.
  float wa[3][2];
  bool upper[3];
  for (int a = 0; a < 3; ++a) {
    wa[a][0] = 1.0f - f[a];
    wa[a][1] = f[a];
    upper[a] = i0[a] + 1 < static_cast<int>(dims[a]);
  }
  const size_t strideY = dims.x, strideZ = size_t{dims.x} * dims.y;
  const size_t base = size_t(i0[2]) * strideZ + size_t(i0[1]) * strideY + size_t(i0[0]);
  const float* record[8];
  float weight[8];
  float weightSum = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    const int hx = corner & 1, hy = (corner >> 1) & 1, hz = corner >> 2;
    const float w = (wa[0][hx] * wa[1][hy]) * wa[2][hz];
    bool use = (!hx || upper[0]) && (!hy || upper[1]) && (!hz || upper[2]);
    const size_t v = use ? base + size_t(hz) * strideZ + size_t(hy) * strideY + size_t(hx) : 0;
    use = use && valid[v] != 0;
    record[corner] = use ? &coefficients[v * kShFloats] : kZero.data();
    weight[corner] = use ? w : 0.0f;
    weightSum = weightSum + weight[corner];
  }
  // Blend the 27 coefficients over the corners, normalize, then dot with the basis.
  // Bit-exactness: every coefficient is its own chain w0 r0 + w1 r1 + ... + w7 r7 in corner
  // order, times 1/sum(w). The chains run four at a time with GCC vector extensions (SSE on
  // x86, NEON on aarch64; -O2 does not vectorize this short loop itself): each lane does the
  // same IEEE operations in the same order as the scalar formula, so the bits are the same
  // on every machine (no FMA: -ffp-contract=off).
  float blended[kShFloats];
  const float* source = blended;
  if (weightSum > 0.0f) {
    using Float4 = float __attribute__((vector_size(16)));
    auto load4 = [](const float* from) {
      Float4 v;
      std::memcpy(&v, from, sizeof v);
      return v;
    };
    constexpr int kVectorFloats = kShFloats / 4 * 4;  // 24; the last 3 run as scalars
    constexpr int kVectors = kVectorFloats / 4;
    // Corner-outer: the six vector chains and three scalar ones are independent, so their
    // additions overlap instead of waiting on one chain's latency.
    Float4 acc[kVectors];
    float tail[kShFloats - kVectorFloats];
    for (int v = 0; v < kVectors; ++v) acc[v] = weight[0] * load4(record[0] + 4 * v);
    for (int q = kVectorFloats; q < kShFloats; ++q)
      tail[q - kVectorFloats] = weight[0] * record[0][q];
    for (int corner = 1; corner < 8; ++corner) {
      const float w = weight[corner];
      const float* r = record[corner];
      for (int v = 0; v < kVectors; ++v) acc[v] = acc[v] + w * load4(r + 4 * v);
      for (int q = kVectorFloats; q < kShFloats; ++q) {
        tail[q - kVectorFloats] = tail[q - kVectorFloats] + w * r[q];
      }
    }
    const float inv = 1.0f / weightSum;
    for (int v = 0; v < kVectors; ++v) acc[v] = acc[v] * inv;
    for (float& x : tail) x = x * inv;
    std::memcpy(blended, acc, sizeof acc);
    std::memcpy(blended + kVectorFloats, tail, sizeof tail);
  } else {
    source = fallback.data();
  }
  glm::vec3 out;
  for (int ch = 0; ch < 3; ++ch) {
    float t[kShCoefficients];
    for (int k = 0; k < kShCoefficients; ++k) t[k] = basis[k] * source[k * 3 + ch];
    out[ch] = (((t[0] + t[1]) + (t[2] + t[3])) + ((t[4] + t[5]) + (t[6] + t[7]))) + t[8];
  }
  // The order-2 reconstruction rings slightly negative behind strong lights.
  for (int ch = 0; ch < 3; ++ch) out[ch] = out[ch] > 0.0f ? out[ch] : 0.0f;
  return out;
}

ToneLut::ToneLut(const ToneCurve& curve)
    : curve_(curve), thresholds_(curve.thresholds()), start_(size_t{1} << 15) {
  for (uint32_t b = 0; b < start_.size(); ++b) {
    start_[b] = curve(double(std::bit_cast<float>(b << 16)));  // NaN buckets: never read
  }
}

uint8_t ToneLut::operator()(float radiance) const {
  if (std::isnan(radiance)) return 0;
  const uint32_t bits = std::bit_cast<uint32_t>(radiance);
  if (bits >> 31) return curve_(double(radiance));  // negative (or -0)
  // Codes only grow within a bucket: scan up from its lowest float's code.
  unsigned code = start_[bits >> 16];
  const double v = radiance;
  while (code < 255 && thresholds_[code] <= v) ++code;
  return static_cast<uint8_t>(code);
}

void shadeVerticesDiffuse(const IrradianceVolume& volume, std::span<const core::Vec3> positions,
                          std::span<const glm::vec3> normals, const glm::vec3& reflectance,
                          const ToneLut& tone, std::span<core::Rgb8> colours,
                          std::span<glm::vec3> radiance) {
  if (normals.size() != positions.size() || colours.size() != positions.size() ||
      (!radiance.empty() && radiance.size() != positions.size())) {
    throw std::invalid_argument("shadeVerticesDiffuse: span sizes differ");
  }
  for (size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3& m = normals[v];
    const float length = std::sqrt(m.x * m.x + m.y * m.y + m.z * m.z);  // sqrt is IEEE-exact
    const float inv = 1.0f / length;
    const glm::vec3 n =
        length > 0.0f ? glm::vec3(m.x * inv, m.y * inv, m.z * inv) : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 e =
        volume.irradianceOverPi(glm::vec3(positions[v].x, positions[v].y, positions[v].z), n);
    const glm::vec3 l(reflectance.x * e.x, reflectance.y * e.y, reflectance.z * e.z);
    if (!radiance.empty()) radiance[v] = l;
    colours[v] = tone.map(l);
  }
}

std::vector<glm::vec3> vertexNormals(const core::Mesh& m) {
  std::vector<glm::vec3> normals(m.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    const core::Vec3 &a = m.positions[m.indices[3 * t]], &b = m.positions[m.indices[3 * t + 1]],
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
