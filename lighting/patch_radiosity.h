// Diffuse light exchange between the room's patches (Gibson & Chalmers 2003 §4.2: "gather
// irradiance from the patch mesh, using ray-casting to evaluate visibility"). Used by the
// light-probe projection (reflectance = radiance / gathered irradiance, and radiance of the
// patches the probe cannot see) and by precompute, which needs every patch's outgoing
// radiance to build the irradiance volume (§5) when the room comes from a scene file.
//
// Gather at patch i: G_i = sum_j L_j F(c_i, n_i -> patch j) V(c_i, c_j), over j != i in
// index order, F the point-to-patch form factor of scene/patch_mesh.h and V one ray from
// centre to centre (Embree). G_i is the irradiance over pi, so a diffuse patch reflects
// rho_i (*) G_i. Cost: one ray per pair of mutually facing patches with L_j != 0.
// Deterministic: each G_i is a fixed-order sum computed on one thread.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "lighting/embree_scene.h"
#include "scene/patch_mesh.h"

namespace penumbra::lighting {

struct GatherOptions {
  unsigned threads = 2;        // 0 = hardware concurrency
  double normalOffset = 1e-4;  // metres off each surface, so a ray does not start inside it
};

// G_i for every patch from `radiance` (one entry per patch). Throws std::invalid_argument
// on a size mismatch.
std::vector<glm::dvec3> gatherPatchIrradiance(const scene::PatchMesh& mesh, const EmbreeScene& rays,
                                              std::span<const glm::dvec3> radiance,
                                              const GatherOptions& options = {});

// Outgoing radiance of every patch after `bounces` Jacobi steps of L = e + rho (*) G(L)
// from L = e (the patches' emission and reflectance): 0 bounces is emission only, 1 adds
// direct light, each further bounce one more interreflection (and N^2 rays).
std::vector<glm::dvec3> solvePatchRadiance(const scene::PatchMesh& mesh, const EmbreeScene& rays,
                                           int bounces, const GatherOptions& options = {});

}  // namespace penumbra::lighting
