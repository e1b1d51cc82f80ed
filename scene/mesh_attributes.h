// Per-vertex normals and reflectances of product meshes: from polygons with per-corner
// attributes (what OBJ, PLY and glTF primitives describe) to the indexed TriangleMesh the
// pipeline shades, one vertex per distinct (position, normal, attribute) so every vertex's
// normal and colour are exact (a cube with 8 shared corners and flat faces becomes 24
// vertices; issue 15 item 6: averaged normals across a crease showed as bands).
//
// Normals a file does not give are computed:
//  - smoothing groups (OBJ `s N`): the corners of faces in the same nonzero group at the same
//    position share one normal; group 0 (`s off`) faces are flat;
//  - otherwise by crease angle: two faces sharing an edge are smooth across it when their
//    normals differ by at most the crease angle (and the edge has exactly these two faces; an
//    edge of three or more faces is a crease); corners at a position share one normal when
//    they are joined through smooth edges around it (as Blender's "auto smooth").
// A shared normal is the area-weighted sum of its faces' normals, normalized. Area weights
// (Gouraud 1971 took the plain mean; area weighting is the common refinement) because they
// need only the cross products the face normals already are — IEEE +, -, * — where angle
// weights (Thürmer & Wüthrich 1998) need acos from libm, whose last bits differ between
// machines; and a polygon's normal is its vector area (the fan of cross products, the same for
// every choice of fan apex, Newell's method), so a quad counts once however it is split.
// Sums run in corner order: the same bits on every machine.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/mesh_io.h"

namespace penumbra::scene {

inline constexpr uint32_t kNoAttribute = ~0u;

// Polygons with per-corner attributes.
struct PolygonSoup {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  // explicit normals (OBJ `vn`, glTF NORMAL), unit length
  // Face f has corners [faceStart[f], faceStart[f + 1]), at least 3 each.
  std::vector<uint32_t> faceStart{0};
  std::vector<uint32_t> cornerPosition;  // index into positions
  std::vector<uint32_t> cornerNormal;    // index into normals, or kNoAttribute (computed)
  // Corners with the same attribute have the same reflectance: index into `reflectances`,
  // or kNoAttribute when `reflectances` is empty.
  std::vector<uint32_t> cornerAttribute;
  std::vector<glm::dvec3> reflectances;  // empty: the mesh has no per-vertex reflectance
  // Per face when smoothingGroups: its group (0 = flat). Otherwise unused.
  std::vector<uint32_t> faceGroup;
  bool smoothingGroups = false;

  size_t faceCount() const { return faceStart.size() - 1; }
  // Appends a face of `corners` corners (the caller pushes their attributes).
  void endFace() { faceStart.push_back(static_cast<uint32_t>(cornerPosition.size())); }
};

// The triangles (fans of each polygon) and vertices as described above. Vertices are numbered
// in the order their first corner appears; unreferenced positions are dropped.
// `creaseAngleDegrees` in [0, 180] (180: smooth everywhere; 0: only coplanar neighbours).
TriangleMesh buildTriangleMesh(const PolygonSoup& soup, double creaseAngleDegrees);

// Area-weighted vector area of polygon `face` (twice its area times its unit normal).
glm::dvec3 polygonVectorArea(const PolygonSoup& soup, size_t face);

}  // namespace penumbra::scene
