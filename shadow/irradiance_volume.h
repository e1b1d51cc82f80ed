// The irradiance volume of Gibson & Chalmers 2003 §5 as the per-frame path reads it: a
// uniform grid over the room, nine spherical-harmonic coefficients (RGB) per grid vertex
// encoding the irradiance arriving from every direction (Ramamoorthi & Hanrahan 2001).
// lighting/irradiance_volume_gather.h gathers it offline from the patch mesh; this file only
// stores and evaluates it, so the board build (no Embree) shades products the same way.
//
// What is stored: for vertex v, coefficient k (the real SH basis Y_k below, k = l^2 + l + m)
// and channel c, the value E_k / pi = (A_l / pi) L_k with A_0 = pi, A_1 = 2 pi / 3,
// A_2 = pi / 4 (R&H 2001 eq. 8–9) and L_k the radiance's SH projection. So
// sum_k coeff_k Y_k(n) is E(n) / pi, the radiance a white Lambertian surface with normal n
// reflects there, and a surface of reflectance rho reflects rho (*) that.
//
// Per-frame evaluation (bit-exact contract, design §3): float, IEEE +, -, *, / only, in the
// order written in the .cpp (no libm, no FMA: the project builds with -ffp-contract=off),
// one vertex at a time, so the bytes do not depend on the ISA, thread count or batch size.
// Cost: one trilinear blend of eight 27-float records (vectorized per SIMD target: each
// coefficient is its own chain in corner order) and nine basis products per vertex; about
// 60 ns on one core.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "raster/frame_trace.h"
#include "shadow/intensity_transfer.h"
#include "shadow/tone_curve.h"
#include "simd/targets.h"

namespace penumbra::shadow {

inline constexpr int kShCoefficients = 9;
inline constexpr int kShFloats = kShCoefficients * 3;  // per grid vertex: [k][rgb]

// The real SH basis of bands 0–2 at a unit direction d (R&H 2001 eq. 3; y is up in this
// project but the basis needs no particular orientation, only the same one in the gather
// and the lookup). Products in the order written: no FMA, same bits everywhere.
template <typename T>
inline void shBasis9(T x, T y, T z, T out[kShCoefficients]) {
  out[0] = T(0.282095);
  out[1] = T(0.488603) * y;
  out[2] = T(0.488603) * z;
  out[3] = T(0.488603) * x;
  out[4] = T(1.092548) * (x * y);
  out[5] = T(1.092548) * (y * z);
  out[6] = T(0.315392) * (T(3) * (z * z) - T(1));
  out[7] = T(1.092548) * (x * z);
  out[8] = T(0.546274) * (x * x - y * y);
}

// A_l / pi per coefficient k (band l = 0, 1, 1, 1, 2, ...).
inline constexpr std::array<double, kShCoefficients> kShIrradianceOverPi = {
    1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25};

struct IrradianceVolume {
  // Grid vertex (i, j, k) sits at origin + (i, j, k) * spacing, i < dims.x etc.
  glm::uvec3 dims{0u};
  glm::vec3 origin{0.0f};
  glm::vec3 spacing{1.0f};
  // kShFloats per vertex, vertex index (k * dims.y + j) * dims.x + i.
  std::vector<float> coefficients;
  // Per vertex: 1 when the vertex sees the room's air (inside the room, outside every
  // solid box); 0 vertices are left out of the trilinear weights.
  std::vector<uint8_t> valid;
  // Used where all eight corners are invalid (a point inside a desk): the mean of the
  // valid vertices' coefficients.
  std::array<float, kShFloats> fallback{};

  bool empty() const { return coefficients.empty(); }
  size_t vertexCount() const { return size_t{dims.x} * dims.y * dims.z; }
  // Throws std::invalid_argument naming the problem: dims < 1, spacing not positive and
  // finite, sizes not matching dims, non-finite coefficients.
  void validate() const;

  // E(n) / pi at `p` for the unit normal `n`: trilinear blend of the valid corners'
  // coefficients (weights renormalized over them; `p` clamped to the grid), dotted with
  // the basis at n. The per-frame lookup.
  glm::vec3 irradianceOverPi(const glm::vec3& p, const glm::vec3& n) const;
};

// The trilinear blend of irradianceOverPi: for q < kShFloats,
//   out[q] = (((w0 r0[q] + w1 r1[q]) + w2 r2[q]) + ... + w7 r7[q]) * inv,
// products and sums rounded one by one in that order. Compiled per SIMD target; every target
// gives the scalar reference's bits (tested on each). irradianceOverPi runs the best one.
using ShCornerBlend = void (*)(const float* const record[8], const float weight[8], float inv,
                               float out[kShFloats]);
ShCornerBlend shCornerBlendFor(simd::Isa isa);

// Diffuse shading of a product's vertices (§5): radiance_v = reflectance (*) E(n_v) / pi,
// then T() per channel. `normals` need not be unit length (zero → +y). `radiance` may be
// empty (not written); otherwise all spans have positions.size() entries.
// `reflectances` holds one reflectance for every vertex or one per vertex.
void shadeVerticesDiffuse(const IrradianceVolume& volume, std::span<const core::Vec3> positions,
                          std::span<const glm::vec3> normals,
                          std::span<const glm::vec3> reflectances, const ToneCurve& tone,
                          std::span<core::Rgb8> colours, std::span<glm::vec3> radiance);
inline void shadeVerticesDiffuse(const IrradianceVolume& volume,
                                 std::span<const core::Vec3> positions,
                                 std::span<const glm::vec3> normals, const glm::vec3& reflectance,
                                 const ToneCurve& tone, std::span<core::Rgb8> colours,
                                 std::span<glm::vec3> radiance) {
  shadeVerticesDiffuse(volume, positions, normals, std::span<const glm::vec3>(&reflectance, 1),
                       tone, colours, radiance);
}

// Area-weighted vertex normals of an indexed mesh (not normalized), summed in triangle order.
std::vector<glm::vec3> vertexNormals(const core::Mesh& mesh);

}  // namespace penumbra::shadow
