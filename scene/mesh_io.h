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

// Loads by extension (.obj, .ply, or .gltf/.glb with PENUMBRA_WITH_GLTF, any case). Throws
// MeshError for an unreadable file, an unknown extension, malformed content or a mesh without
// triangles.
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
