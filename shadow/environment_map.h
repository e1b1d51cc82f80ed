// Specular reflection of the room on a product (Gibson & Chalmers 2003 §5, Fig. 9): a small
// cube environment map rendered from the product's centre by the project's own rasterizer
// each time the product moves, and a Phong-like lobe looked up in it per vertex.
//
// What the map holds: the room's patch mesh drawn as a Gouraud-shaded object whose vertex
// colours are T(L_v), L_v the mean outgoing radiance of the vertex's patches — 8-bit and
// tone-mapped, as in the tutorial, because the rasterizer's colour path is 8-bit. A lookup
// turns a code back into radiance through T's inverse at the middle of the code's interval
// (ToneInverse), so the specular term is added to the diffuse one in radiance and the sum
// goes through T() once.
//
// Lobe: for reflection direction r (the eye direction mirrored in the normal), a fixed
// pattern of kLobeRings x kLobeAzimuths directions around r whose polar cosines split the
// Phong lobe cos^N into equal-energy rings (N = the product's exponent rounded to an
// integer, ring cosines found by bisection on c^(N + 1) with multiplications only), eight
// azimuths 45 degrees apart; the looked-up radiances are averaged in pattern order.
// Everything is IEEE +, -, *, /, sqrt in a fixed order: same bytes on every ISA.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "raster/frame_trace.h"
#include "shadow/intensity_transfer.h"
#include "shadow/tone_curve.h"

namespace penumbra::shadow {

inline constexpr int kLobeRings = 4;
inline constexpr int kLobeAzimuths = 8;

// Cube faces in the order +x, -x, +y, -y, +z, -z.
struct CubeEnvironmentMap {
  uint32_t size = 0;          // pixels per face side
  std::vector<uint8_t> rgba;  // 6 faces x size x size x 4, row 0 at the top of a face
  glm::vec3 centre{0.0f};     // where it was rendered from

  // The texel the unit direction d falls on (nearest), as radiance through `inverse`.
  glm::vec3 lookup(const glm::vec3& d, const ToneInverse& inverse) const;
};

// The room as the map draws it: `mesh` with per-vertex T(mean radiance of the vertex's
// patches). `patchRadiance` has one entry per patch, `trianglePatch` one per triangle.
raster::ShadedMesh roomForEnvironment(const core::Mesh& mesh,
                                      std::span<const uint32_t> trianglePatch,
                                      std::span<const glm::vec3> patchRadiance,
                                      const ToneCurve& tone);

// Renders the six faces (90-degree frusta, near 0.01 m, far `farDistance`) around `centre`
// with raster::Renderer (one thread; bytes independent of it anyway).
void renderEnvironmentMap(const raster::ShadedMesh& room, const glm::vec3& centre, uint32_t size,
                          float farDistance, CubeEnvironmentMap& out);

// The lobe pattern for a Phong exponent: kLobeRings (cos, sin) pairs of polar angles.
struct PhongLobe {
  std::array<float, kLobeRings> cosTheta{}, sinTheta{};
  uint32_t roundedExponent = 0;  // N: the exponent rounded to an integer
  explicit PhongLobe(float exponent = 1.0f);
};

// c^k for a non-negative integer k by squaring (multiplications only, in a fixed order).
double powInt(double c, uint32_t k);

// Mean radiance of the room reflected about `normal` towards `eye` from `position`, over
// the lobe pattern. `normal` need not be unit length (zero → no reflection, returns 0).
glm::vec3 specularRadiance(const CubeEnvironmentMap& map, const ToneInverse& inverse,
                           const PhongLobe& lobe, const glm::vec3& position,
                           const glm::vec3& normal, const glm::vec3& eye);

}  // namespace penumbra::shadow
