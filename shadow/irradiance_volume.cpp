#include "shadow/irradiance_volume.h"

#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shadow/irradiance_volume.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

// The corner blend per SIMD target (shCornerBlendFor). Each lane runs one coefficient's chain
// with the scalar reference's IEEE operations in its order (Mul then Add, never MulAdd:
// design §6), so every target gives the reference's bits.
HWY_BEFORE_NAMESPACE();
namespace penumbra::shadow::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Chains [first, first + kVectors * lanes) of the blend. Corner-outer: the kVectors chains
// are independent, so their additions overlap instead of waiting on one chain's latency.
template <size_t kVectors, class D>
HWY_INLINE void BlendChains(D d, const float* const record[8], const float weight[8], float inv,
                            size_t first, float* out) {
  constexpr size_t kLanes = hn::MaxLanes(D());
  hn::Vec<D> acc[kVectors];
  for (size_t v = 0; v < kVectors; ++v) {
    acc[v] = hn::Mul(hn::Set(d, weight[0]), hn::LoadU(d, record[0] + first + v * kLanes));
  }
  for (int corner = 1; corner < 8; ++corner) {
    const hn::Vec<D> w = hn::Set(d, weight[corner]);
    for (size_t v = 0; v < kVectors; ++v) {
      acc[v] = hn::Add(acc[v], hn::Mul(w, hn::LoadU(d, record[corner] + first + v * kLanes)));
    }
  }
  for (size_t v = 0; v < kVectors; ++v) {
    hn::StoreU(hn::Mul(acc[v], hn::Set(d, inv)), d, out + first + v * kLanes);
  }
}

void BlendCorners(const float* const record[8], const float weight[8], float inv,
                  float out[kShFloats]) {
  // 8 lanes on AVX2 and AVX-512 (3 vectors: a 16-lane vector would leave 11 chains over),
  // 4 on SSE4 and NEON (6 vectors); the last 3 chains run in one-lane vectors.
  const hn::CappedTag<float, 8> d;
  constexpr size_t kVectors = kShFloats / hn::MaxLanes(decltype(d)());
  constexpr size_t kVectorFloats = kVectors * hn::MaxLanes(decltype(d)());
  BlendChains<kVectors>(d, record, weight, inv, 0, out);
  if constexpr (kVectorFloats < kShFloats) {  // not on Highway's one-lane scalar target
    BlendChains<kShFloats - kVectorFloats>(hn::CappedTag<float, 1>(), record, weight, inv,
                                           kVectorFloats, out);
  }
}

ShCornerBlend BlendCornersKernel() {
  return &BlendCorners;
}

}  // namespace penumbra::shadow::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/target_table.h"

namespace penumbra::shadow {
namespace {

// The reference the targets must match, in the order irradiance_volume.h states.
void blendCornersScalar(const float* const record[8], const float weight[8], float inv,
                        float out[kShFloats]) {
  for (int q = 0; q < kShFloats; ++q) out[q] = weight[0] * record[0][q];
  for (int corner = 1; corner < 8; ++corner) {
    for (int q = 0; q < kShFloats; ++q) out[q] = out[q] + weight[corner] * record[corner][q];
  }
  for (int q = 0; q < kShFloats; ++q) out[q] = out[q] * inv;
}

}  // namespace

ShCornerBlend shCornerBlendFor(simd::Isa isa) {
  if (isa == simd::Isa::kScalar) return &blendCornersScalar;
  return PENUMBRA_TARGET_TABLE_LOOKUP(BlendCornersKernel, isa);
}

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
  // Blend the 27 coefficients over the corners (shCornerBlendFor), normalize, then dot with
  // the basis.
  float blended[kShFloats];
  const float* source = blended;
  if (weightSum > 0.0f) {
    // The widest target this CPU runs: all give the same bits (simd/targets.h).
    static const ShCornerBlend blend = shCornerBlendFor(simd::bestIsa());
    blend(record, weight, 1.0f / weightSum, blended);
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

void shadeVerticesDiffuse(const IrradianceVolume& volume, std::span<const core::Vec3> positions,
                          std::span<const glm::vec3> normals,
                          std::span<const glm::vec3> reflectances, const ToneCurve& tone,
                          std::span<core::Rgb8> colours, std::span<glm::vec3> radiance) {
  if (normals.size() != positions.size() || colours.size() != positions.size() ||
      (!radiance.empty() && radiance.size() != positions.size()) ||
      (reflectances.size() != 1 && reflectances.size() != positions.size())) {
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
    const glm::vec3& reflectance = reflectances[reflectances.size() == 1 ? 0 : v];
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
#endif  // HWY_ONCE
