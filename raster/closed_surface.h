// Whether an occluder may be drawn into its shadow maps front faces only (back-face
// culling, raster::ShadowPass::cullBackFaces).
//
// Why that draws the same map: a ray from a light outside a closed surface enters it as
// often as it leaves, so every texel centre an occluder triangle covers is covered by at
// least one triangle facing the light too, and the nearest of its hits is an entering one.
// After snapping the same holds for the covered samples exactly: the snapped triangles
// still form a closed oriented surface, the fill rule splits every shared edge between its
// two triangles, so at every sample the facing and the away-facing triangles' coverage
// counts are equal. Only the depth of a sample next to the silhouette may differ, where a
// nearly edge-on triangle's snapped winding flips; the showroom's proxies draw identical
// frames (docs/performance.md). An open mesh (the Utah teapot's holes) has no such promise:
// a ray can leave through a hole, so it keeps both faces.
#pragma once

#include "core/geometry.h"

namespace penumbra::raster {

// True when every edge of `mesh` is shared by exactly two triangles that traverse it in
// opposite directions (closed, consistently wound, no seams: a vertex split along a seam
// reads as open) and every connected piece encloses a positive volume, i.e. its triangles
// wind counter-clockwise seen from outside. Degenerate triangles (a repeated index) make it
// false. O(triangles log triangles); the signed volumes are summed in triangle order.
bool isClosedOutwardSurface(const core::Mesh& mesh);

}  // namespace penumbra::raster
