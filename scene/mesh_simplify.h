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

// At most `targetTriangles` triangles approximating `mesh`. The welded mesh is reduced by
// quadric edge collapse (meshopt_simplify) on its own vertex positions; when topology
// stops it short of the target (open borders, separate parts) the rest is done by vertex
// clustering (meshopt_simplifySloppy). The result is then pushed out along its vertex
// normals by medianDistanceOutside(welded mesh, result) when that is positive, so that it
// no longer lies inside the model but halfway (its shadow neither small nor large).
// Deterministic. A mesh already within the target is returned welded, unmoved. Throws
// std::invalid_argument when targetTriangles < 4.
// The median over `model`'s vertices of the signed distance to the closest point of
// `proxy` (positive outside, by the proxy's counter-clockwise winding; ties to the first
// triangle). 0 for an empty model or proxy. O(vertices × triangles).
double medianDistanceOutside(const TriangleMesh& model, const TriangleMesh& proxy);

// With `solid`, the welded mesh's holes are capped first (capHoles, when its boundary is a
// set of simple loops), so that a closed proxy comes from a closed model, within the same
// budget.
TriangleMesh simplifyForShadows(const TriangleMesh& mesh, size_t targetTriangles,
                                bool solid = false);

}  // namespace penumbra::scene
