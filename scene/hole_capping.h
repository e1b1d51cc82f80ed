// Capping a solid product's shadow proxy (scene key `solid`): every hole in its surface is
// closed by a fan of triangles, so the proxy encloses what the product does and can be drawn
// into shadow maps front faces only (raster/closed_surface.h).
//
// Scanned and modelled products are often open where nobody looks: the Utah teapot between
// its lid and its rim, at its spout's tip, where spout and handle meet the body. A solid
// object lets no light through there, and a proxy with holes cannot be culled, so each of
// its passes draws twice the triangles. Not every product is solid: a lampshade's openings
// let light through, which is why capping is asked for per product, not done by default.
#pragma once

#include <cstddef>
#include <optional>

#include "scene/mesh_io.h"

namespace penumbra::scene {

// Closes every boundary loop of `mesh` (a directed edge a -> b whose reverse no triangle
// has) with a fan from the loop's centroid: triangles (b, a, centroid), which traverse each
// boundary edge the other way, so the cap joins the surface with consistent winding. Returns
// the number of loops capped, or nullopt, leaving `mesh` unchanged, when the boundary is not
// a set of simple loops (a vertex with two outgoing boundary edges, an edge used twice in
// one direction). The caps' vertices are appended; normals and reflectances, which a proxy
// does not use, are cleared.
std::optional<size_t> capHoles(TriangleMesh& mesh);

}  // namespace penumbra::scene
