// glTF 2.0 products (.gltf with embedded or side-by-side buffers, .glb), the format
// e-commerce catalogues ship, read with tinygltf. Built with PENUMBRA_WITH_GLTF
// (PENUMBRA_HAVE_GLTF defined); scene files and loadMesh() accept .gltf/.glb then.
//
// Geometry: every TRIANGLES primitive of every mesh instanced by the default scene's node
// tree (all root nodes when the file has no scene), positions through the node's world
// transform (matrix, or translation * rotation * scale), indices of any integer type or
// none. Mirroring transforms get their triangles' winding swapped so the faces still face
// out. Points, lines, strips and fans are skipped; sparse accessors are refused.
//
// Normals: NORMAL through the inverse transpose of the node's world matrix (perpendicular
// under non-uniform scale, the right way round under a mirror), normalized; a primitive
// without NORMAL gets flat normals (glTF 2.0 §3.7.2.1: "client implementations MUST calculate
// flat normals"; coplanar neighbours share vertices).
//
// Colour, per vertex (TriangleMesh::reflectances): base colour = baseColorFactor.rgb (*) the
// base-colour texture sampled bilinearly at the vertex's TEXCOORD_n (sRGB decoded to linear,
// the sampler's wrap modes; scene/texture.h) (*) COLOR_0, mapped to a diffuse reflectance
// below. Per vertex, not per pixel: a texture finer than the mesh loses its detail between
// vertices. A texture without its TEXCOORD set contributes its mean colour (with a warning).
//
// Material, per primitive, then a triangle-weighted mean over the model (the product's one
// specular lobe): base colour c = baseColorFactor.rgb (*) the mean of the base-colour
// texture's texels; metallic m and roughness r from their factors (textures of those are not
// read). Mapped to our diffuse + Phong-like lobe (Gibson & Chalmers 2003 §5) by
// mapMetallicRoughness:
//   diffuse reflectance  = c (1 - m)                 (metals have no diffuse term)
//   specular reflectance = 0.04 (1 - m) + c m        (F0 of a dielectric; tinted metals)
//   Phong exponent       = 2 / alpha^2 - 2, alpha = max(r^2, 0.001), clamped to [1, 4096]
//                          (the Blinn-Phong exponent matching a GGX/Beckmann lobe of
//                          width alpha; r = 1 gives the broadest lobe, exponent 1).
// glTF's default material (a primitive without one) is c = 1, m = 1, r = 1.
#pragma once

#include <filesystem>

#include <glm/glm.hpp>

#include "scene/mesh_io.h"

namespace penumbra::scene {

struct ProductMaterial {
  glm::dvec3 baseColour{1.0};
  double metallic = 1, roughness = 1;
  glm::dvec3 diffuse{0.0};   // reflectance per channel, [0, 1]
  glm::dvec3 specular{0.0};  // reflectance per channel, [0, 1]
  double specularExponent = 1;
};

// The mapping above, for base colour c in [0, 1] and m, r clamped to [0, 1].
ProductMaterial mapMetallicRoughness(const glm::dvec3& baseColour, double metallic,
                                     double roughness);

struct GltfModel {
  TriangleMesh mesh;         // model units, the file's axes (glTF: y up, metres); normals,
                             // per-vertex diffuse reflectances and warnings
  ProductMaterial material;  // triangle-weighted mean over the primitives
};

#ifdef PENUMBRA_HAVE_GLTF
// Throws MeshError "FILE: what" for unreadable or corrupt files (tinygltf's own message
// included), accessors out of their buffers, non-finite positions, node cycles, or a model
// without triangles.
GltfModel loadGltf(const std::filesystem::path& path);
#endif

}  // namespace penumbra::scene
