// Triangle meshes of showroom products read from OBJ and PLY files (and glTF, gltf_io.h):
// positions, faces, and per-vertex normals and diffuse reflectances. Polygons are triangulated
// as fans, which is exact for the convex faces modelling tools write.
//
// Vertices are unwelded where a position carries different normals or colours (a vertex is a
// distinct (position, normal, colour) tuple, scene/mesh_attributes.h), so a box of 8 shared
// corners with flat faces has 24 vertices and shades without bands.
//
// OBJ: `v`, `vt`, `vn`, `f` with i, i/t, i//n, i/t/n corners; `s` smoothing groups; `mtllib`
// and `usemtl` with the material's `Kd` and `map_Kd` (read relative to the .mtl file, sampled
// at each vertex's uv, texture.h). Normals come from `vn` where a corner has one, else from
// the smoothing groups, else by crease angle (MeshOptions). PLY: normals by crease angle.
//
// Every malformed input throws MeshError, whose message names the file, the line (OBJ,
// MTL, ASCII PLY) or the element (binary PLY) and the problem, so a bad model dropped into a
// showroom folder is diagnosed from the kiosk's log alone. A missing .mtl or texture file is
// an error naming it (the model was exported with them: without them it would show the wrong
// colours). A texture this build cannot decode (JPEG in a build without tinygltf) is not the
// file's fault: a warning (TriangleMesh::warnings) names it and the material keeps its Kd.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
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
  // Empty, or one unit normal per position (the loaders always give them).
  std::vector<glm::dvec3> normals;
  // Empty (the product's colour comes from the scene file), or one diffuse reflectance per
  // position: linear RGB in [0, 1] (OBJ Kd x map_Kd, glTF base colour x (1 - metallic)).
  std::vector<glm::dvec3> reflectances;
  // What the loader could not honour but did not refuse, each naming the file ("a.mtl: line 4:
  // texture.jpg: no JPEG decoder in this build; the material's Kd is used"). Callers print them.
  std::vector<std::string> warnings;

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

// Normals a file does not give are split where faces meet at more than this angle
// (mesh_attributes.h). 60 degrees: a box (90) and a chair's legs against its seat stay sharp,
// while curved surfaces tessellated at the density of catalogue models (the teapot's
// neighbouring faces differ by under 30 degrees) stay smooth. It is the default of Unity's
// model importer ("Smoothing Angle") and of three.js's toCreasedNormals. A scene file's
// product key `crease_angle_deg` changes it.
inline constexpr double kDefaultCreaseAngleDegrees = 60;

struct MeshOptions {
  double creaseAngleDegrees = kDefaultCreaseAngleDegrees;  // in [0, 180]
  // Reads a file the model names (OBJ mtllib, map_Kd), already resolved against the naming
  // file's folder. The default reads regular files of at most kMaxModelFileBytes and throws
  // core::Error naming the path; the fuzzers give files from memory.
  std::function<std::string(const std::filesystem::path&)> readFile = readModelFile;

  static std::string readModelFile(const std::filesystem::path& path);
};

// Loads by extension (.obj, .ply, or .gltf/.glb with PENUMBRA_WITH_GLTF, any case). Throws
// MeshError for an unreadable file or one that is not a regular file (a directory,
// /dev/zero), an unknown extension, malformed content, a mesh without triangles or one
// beyond the limits above.
TriangleMesh loadMesh(const std::filesystem::path& path, const MeshOptions& options = {});

// Wavefront OBJ: `v x y z [w]`, `vt u [v [w]]`, `vn x y z`, `f` with 1-based or negative
// (relative) indices in any of the forms i, i/t, i//n, i/t/n, `s N|off`, `mtllib FILE...` and
// `usemtl NAME`; other statements (g, o, l, p, ...) are ignored. `name` is used in messages
// and its folder anchors mtllib files. MTL: `newmtl`, `Kd r [g b]` in [0, 1], `map_Kd
// [-clamp on|off] [-o u [v]] [-s u [v]] [other options] FILE`; other statements are ignored.
// A face without a material in a file whose other faces have one gets Blender's default
// base colour, 0.8 grey, with a warning.
TriangleMesh parseObj(std::string_view text, const std::string& name,
                      const MeshOptions& options = {});

// PLY 1.0, ascii or binary_little_endian: a `vertex` element with x, y, z of any scalar
// type, a `face` element with a list property vertex_indices (or vertex_index) of
// integers; other elements and properties are read and skipped. `name` is used in
// messages.
TriangleMesh parsePly(std::string_view bytes, const std::string& name,
                      const MeshOptions& options = {});

// Writes `v` and `f` lines with 17 significant digits (positions round-trip exactly); normals
// and reflectances are not written.
// Throws MeshError when the file cannot be written.
void saveObj(const TriangleMesh& mesh, const std::filesystem::path& path);

}  // namespace penumbra::scene
