// Occluder proxies: a product's full model reduced to the 100-500 triangles Gibson et al.
// 2003 §7.2 render into the shadow maps (the shadow's outline needs the silhouette, not
// the fur of a scanned bunny; every proxy triangle is drawn once per light source).
#pragma once

#include <cstddef>

#include "scene/mesh_io.h"

namespace penumbra::scene {

// Merges vertices with equal positions (after rounding to float, the precision the
// simplifier works in) and drops triangles that then repeat an index. Vertices keep the
// first-seen order; positions keep their double values. Unreferenced vertices are removed.
TriangleMesh weldVertices(const TriangleMesh& mesh);

// At most `targetTriangles` triangles approximating `mesh`, using only its own vertex
// positions (no vertex moves, so the proxy never grows past the model). The welded mesh
// is reduced by quadric edge collapse (meshopt_simplify); when topology stops it short of
// the target (open borders, separate parts) the rest is done by vertex clustering
// (meshopt_simplifySloppy). Deterministic. A mesh already within the target is returned
// welded. Throws std::invalid_argument when targetTriangles < 4.
TriangleMesh simplifyForShadows(const TriangleMesh& mesh, size_t targetTriangles);

}  // namespace penumbra::scene
