// Fitting a shadow-map frustum to an occluder, and the conservative receiver test that
// goes with it (Gibson 2003 §7.2: "initialising the projection and model-view matrices so
// the synthetic object is contained entirely within the shadow-map, as seen from the
// source patch").
#pragma once

#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"

namespace penumbra::shadow {

struct LightFrustum {
  glm::dmat4 viewProj{1.0};   // world -> light clip space, GL conventions, double
  core::Mat4 rasterViewProj;  // the same, rounded to float once (the trace's matrix)
  glm::dvec3 sphereCentre{0.0};
  double sphereRadius = 0;
  double zNear = 0, zFar = 0;
  double tanHalfFovY = 0;     // tan of half the field of view; the map is square (aspect 1)
  bool orthographic = false;  // a distant light's (fitDirectionalFrustum): tanHalfFovY is 0
};

// The world axis least aligned with direction `f` (ties: x, then y): an up vector for lookAt
// that never degenerates (a ceiling light looking straight down at the object), and a
// vector never parallel to f for building a frame around it.
glm::dvec3 leastAlignedAxis(const glm::dvec3& f);

// Closest distance to the source at which the near plane may sit (1 mm): a closer plane
// would spend the whole depth range of the map on the first millimetres.
inline constexpr double kMinLightNear = 1e-3;

// A perspective view-projection from the point `source` looking at the centre of the
// bounding sphere of `occluderBounds`: the field of view just encloses the sphere, the
// near plane sits just in front of it (at least kMinLightNear) and the far plane at
// `farDistance` from the source (pass the room's extent so every receiver is in range).
// Returns nullopt when the source lies inside the sphere (no frustum can hold the
// object; the caller skips that source) or the bounds are empty or not finite.
std::optional<LightFrustum> fitLightFrustum(const glm::dvec3& source,
                                            const scene::Aabb& occluderBounds, double farDistance);

// A distant light's frustum (Havran et al. 2005: each environment light is directional): an
// orthographic view-projection looking along -`towardsLight` (from the scene towards the
// light; any positive length) at the bounding sphere of `occluderBounds`. The map's window is
// the box projected across the light with 3% of its extent added on each side (so the texels
// are square only for a square projection). The eye sits on the light's side of the sphere,
// the near plane just in front of it, the far plane beyond every corner of `room` (every
// receiver is in range). Window depth is then linear in distance: zFar - zNear metres span
// [0, 1]. Returns nullopt for empty or non-finite bounds or a zero or non-finite direction.
std::optional<LightFrustum> fitDirectionalFrustum(const glm::dvec3& towardsLight,
                                                  const scene::Aabb& occluderBounds,
                                                  const scene::Aabb& room);

// Conservative receiver test: false only when all three vertices lie outside one plane of
// the frustum's clip volume (x, y = ±w, the near plane just in front of the occluder and
// the far plane). Points behind the source are handled because each test is a half-space
// in homogeneous coordinates. A true result may still receive no shadow.
bool triangleMayReceive(const glm::dmat4& lightViewProj, const glm::dvec3& a, const glm::dvec3& b,
                        const glm::dvec3& c);

// The planes of that clip volume `p` lies outside of, as bits (bit k: plane k of w + x,
// w - x, w + y, w - y, w + z, w - z >= 0). triangleMayReceive(a, b, c) is exactly
// (clipOutcode(a) & clipOutcode(b) & clipOutcode(c)) == 0, so a mesh's triangles can share
// their vertices' codes: one transform per vertex instead of one per corner.
uint8_t clipOutcode(const glm::dmat4& lightViewProj, const glm::dvec3& p);

}  // namespace penumbra::shadow
