// Precomputed radiance transfers from source patches to receiver vertices (Gibson 2003
// §5), and the camera visibility that defines the receiver set (§4).
//
// For source patch j and receiver vertex i (position x_i, normal n_i):
//
//   L_ij = rho_i (*) L_j * F(x_i -> patch j) * V_ij,
//
// rho_i the vertex reflectance (mean of its patches'), L_j the patch's emitted radiance,
// F the analytic point-to-polygon form factor (lighting/form_factor.h) and V_ij the
// fraction of a stratified sample pattern on patch j that x_i sees ("an estimate of the
// point-to-patch visibility obtained using ray-casting"). L_ij is the radiance x_i would
// lose towards the camera if patch j were hidden, which is what §7 subtracts.
//
// Determinism (docs/design.md §3): every L_ij is a pure function of (mesh, i, j, options)
// — the jitter comes from a counter-based hash keyed by (seed, vertex, patch), not from a
// running generator — and every sum runs in a fixed order on one thread, so the result is
// the same bytes for any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "lighting/embree_scene.h"
#include "scene/patch_mesh.h"
#include "shadow/light_transport.h"

namespace penumbra::lighting {

struct TransferOptions {
  // V_ij uses samplesPerSide^2 shadow rays, one per cell of a jittered grid on the patch.
  int samplesPerSide = 4;
  uint64_t seed = 0x5452414E53464552ull;  // "TRANSFER"
  // Entries with luminance <= relativeThreshold x (max over receiver vertices of the
  // luminance of L_i) are dropped from the sparse rows (§5 "stored with the source patch";
  // §6 discards insignificant transfers anyway). 0 keeps every non-zero entry.
  double relativeThreshold = 1e-6;
  // Worker threads over emitting patches; 0 = std::thread::hardware_concurrency().
  unsigned threads = 1;
  // Shadow rays start this far (metres) along n_i off the receiver surface, so the
  // receiver's own triangles are not hit.
  double normalOffset = 1e-4;
};

// The four corners of a patch, wound counter-clockwise about its normal: the two
// triangles (a, b, c), (a, c, d) of buildPatchMesh give (a, b, c, d). Throws
// std::invalid_argument when the triangles do not share that diagonal.
std::array<glm::dvec3, 4> patchPolygon(const scene::PatchMesh& mesh, uint32_t patch);

// The key of the visibility sample pattern between mesh vertex `vertex` and patch
// `patch`: stable ids, so a pair keeps its pattern whatever the receiver and source sets.
uint64_t visibilitySampleKey(uint64_t seed, uint32_t vertex, uint32_t patch);

// V: the fraction of the samplesPerSide^2 jittered samples (pattern `key`) on the
// parallelogram polygon[0] + s (polygon[1] - polygon[0]) + t (polygon[3] - polygon[0])
// that are unoccluded from x + normalOffset * n. Only samples in front of the receiver
// count (the form factor already clipped the rest away); when none is, the centroid of
// the clipped polygon decides. Returns 0 when the polygon is wholly behind.
double pointToPatchVisibility(const EmbreeScene& rays, const glm::dvec3& x, const glm::dvec3& n,
                              const std::array<glm::dvec3, 4>& polygon, int samplesPerSide,
                              uint64_t key, double normalOffset);

// §5. Receiver vertices are the distinct mesh vertices of the receiver patches' triangles,
// in increasing vertex index. vertexRadiance sums the vertex's own emission (mean of its
// patches') and the transfer from every emitting patch of the mesh, in patch-index order;
// the sparse rows and sourceAverage cover sets.sources in their order. Throws
// std::invalid_argument for patch indices out of range, samplesPerSide < 1, or a negative
// or non-finite threshold.
shadow::RadianceTransfers computeRadianceTransfers(const scene::PatchMesh& mesh,
                                                   const shadow::SourceReceiverSets& sets,
                                                   const EmbreeScene& rays,
                                                   const TransferOptions& options = {});

// §4 receiver set: per patch, 1 when the first hit of some pixel-centre camera ray lies on
// one of its triangles. Pixel (px, py) (row 0 at the top) casts the ray from the
// unprojected near-plane point of NDC ((px + 0.5) / (width / 2) - 1,
// 1 - (py + 0.5) / (height / 2)) to the far-plane point, so only hits inside the view
// frustum's depth range count, as in the rasterizer. Throws std::invalid_argument for a
// zero size or a singular viewProj.
std::vector<uint8_t> patchesVisibleFromCamera(const scene::PatchMesh& mesh, const EmbreeScene& rays,
                                              const glm::dmat4& viewProj, uint32_t width,
                                              uint32_t height);
// The same, building a scene from `mesh` for the one query.
std::vector<uint8_t> patchesVisibleFromCamera(const scene::PatchMesh& mesh,
                                              const glm::dmat4& viewProj, uint32_t width,
                                              uint32_t height);

}  // namespace penumbra::lighting
