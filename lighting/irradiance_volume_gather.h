// Building the irradiance volume of Gibson & Chalmers 2003 §5 offline: a uniform grid over
// the room, and at each grid vertex the nine SH coefficients of the irradiance arriving
// from the patch mesh, with visibility (Embree). shadow/irradiance_volume.h stores and
// evaluates it per frame; the coefficient convention (E_k / pi) is documented there.
//
// Per grid vertex x:
//  * Emitting patches j are small sources, taken exactly once each: direction to the
//    centre, solid angle A_j cos_j / (r^2 + A_j / pi) (the disc approximation behind
//    scene::pointToPatchFormFactor), one visibility ray, radiance e_j.
//  * Everything else (light reflected by the room, including the reflected part L_j - e_j of
//    emitters) by ray casting in directionsPerSide x 2 directionsPerSide stratified
//    directions over the sphere (rows at equal steps of cos theta, equally spaced azimuths
//    per row, each row turned by a counter-based hash of (seed, vertex, row) — never by a
//    running generator or the thread order).
//  * Validity: a vertex inside a solid box or outside the room sees back faces (the patch
//    mesh's normals face the air) or nothing; when more than invalidShare of its rays do,
//    it is flagged invalid and the per-frame lookup leaves it out.
// Every vertex is computed on one thread with sums in sample order, so the volume is the
// same bytes for any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>

#include <glm/glm.hpp>

#include "lighting/embree_scene.h"
#include "scene/patch_mesh.h"
#include "shadow/irradiance_volume.h"

namespace penumbra::lighting {

struct IrradianceVolumeOptions {
  glm::uvec3 dims{20, 10, 20};            // grid vertices per axis (the tutorial's 20x10x20)
  int directionsPerSide = 12;             // n: n x 2n stratified directions per vertex
  uint64_t seed = 0x4952524144564F4Cull;  // "IRRADVOL"
  unsigned threads = 2;                   // 0 = hardware concurrency
  double invalidShare = 0.1;
  double normalOffset = 1e-4;  // metres: emitter sample points are pulled off their surface
};

// Grid over the mesh's bounding box, vertices at cell centres (dims cells per axis, so no
// vertex lies on a wall). `patchRadiance`: outgoing radiance per patch (e.g. from
// solvePatchRadiance or a light probe). Throws std::invalid_argument for a size mismatch,
// dims < 1, directionsPerSide < 1 or an empty mesh.
shadow::IrradianceVolume buildIrradianceVolume(const scene::PatchMesh& mesh,
                                               const EmbreeScene& rays,
                                               std::span<const glm::dvec3> patchRadiance,
                                               const IrradianceVolumeOptions& options = {});

// The stored coefficients (E_k / pi, [k][rgb]) of a distant radiance function L(direction),
// from the same stratified directions (pattern `key`) the builder uses. For tests and for
// probes at infinity.
std::array<double, shadow::kShFloats> projectIrradianceSh(
    const std::function<glm::dvec3(const glm::dvec3& direction)>& radiance, int directionsPerSide,
    uint64_t key);

// Direction `sample` (0 .. 2 n^2 - 1) of the stratified pattern `key`: unit length, each
// standing for a solid angle of 4 pi / (2 n^2).
glm::dvec3 stratifiedSphereDirection(int directionsPerSide, uint64_t key, int sample);

}  // namespace penumbra::lighting
