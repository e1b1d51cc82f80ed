// Triangle meshes of showroom products read from OBJ and PLY files. Only geometry is
// read (positions and faces): the shadow pipeline needs the occluder's shape, and the
// product's colour comes from the scene file. Polygons are triangulated as fans, which is
// exact for the convex faces modelling tools write.
//
// Every malformed input throws MeshError, whose message names the file, the line (OBJ,
// ASCII PLY) or the element (binary PLY) and the problem, so a bad model dropped into a
// showroom folder is diagnosed from the kiosk's log alone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "scene/patch_mesh.h"

namespace penumbra::scene {

struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<uint32_t> indices;  // 3 per triangle, each < positions.size()

  size_t triangleCount() const { return indices.size() / 3; }
  // Bounds of the referenced and unreferenced positions alike (empty box when none).
  Aabb bounds() const;
};

class MeshError : public core::Error {
 public:
  using core::Error::Error;
};

// Limits by design (docs/input-limits.md, "Models"): a model is a showroom product, and a
// file beyond these is refused before its size can cost time or memory. Each loader checks
// them while it reads, so a lying count or a huge face fails after bounded work.
//
// Triangles: a product scan (the Stanford bunny has 69k triangles, the dragon 871k) fits
// in a million; the frame loop only ever draws the simplified proxy (100-500 triangles,
// Gibson 2003 §7.2), and a million triangles keep a loaded mesh under 100 MB.
constexpr size_t kMaxMeshTriangles = 1'000'000;
// Vertices: three per triangle, what an unwelded glTF primitive has.
constexpr size_t kMaxMeshVertices = 3 * kMaxMeshTriangles;
// Corners of one polygon (OBJ `f`, PLY face list): modelling tools write triangles, quads
// and the caps of cylinders; anything longer is a corrupt line, not a face.
constexpr size_t kMaxFaceCorners = 1024;
// Coordinates in model units: a kilometre in millimetres. A finite but absurd vertex
// (1e308) would overflow once scaled or converted to the float meshes of a bundle.
constexpr double kMaxModelCoordinate = 1e6;
// File size (OBJ, PLY, glTF and its buffers and images): a million-triangle ASCII OBJ is
// about 60 MB.
constexpr uintmax_t kMaxModelFileBytes = uintmax_t{256} << 20;

// Loads by extension (.obj, .ply, or .gltf/.glb with PENUMBRA_WITH_GLTF, any case). Throws
// MeshError for an unreadable file or one that is not a regular file (a directory,
// /dev/zero), an unknown extension, malformed content, a mesh without triangles or one
// beyond the limits above.
TriangleMesh loadMesh(const std::filesystem::path& path);

// Wavefront OBJ: `v x y z [w]` and `f` with 1-based or negative (relative) indices in
// any of the forms i, i/t, i//n, i/t/n. Other statements (vt, vn, g, o, s, usemtl, l, ...)
// are ignored. `name` is used in messages.
TriangleMesh parseObj(std::string_view text, const std::string& name);

// PLY 1.0, ascii or binary_little_endian: a `vertex` element with x, y, z of any scalar
// type, a `face` element with a list property vertex_indices (or vertex_index) of
// integers; other elements and properties are read and skipped. `name` is used in
// messages.
TriangleMesh parsePly(std::string_view bytes, const std::string& name);

// Writes `v` and `f` lines with 17 significant digits (positions round-trip exactly).
// Throws MeshError when the file cannot be written.
void saveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace penumbra::scene
