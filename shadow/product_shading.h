// Product shading (design §1, per frame step 2): the placed product's colour per vertex,
// through the camera response T(), with the model's own normals and per-vertex reflectances
// (issue 15 item 6) where the bundle has them. With an irradiance volume in the bundle (Gibson &
// Chalmers 2003 §5): reflectance x E(n)/pi from the volume's SH9 lookup, plus the §5
// specular lobe from a small cube map of the room rendered at the product's centre
// (Fig. 9). Without one: a flat diffuse material lit by every emitting patch, unshadowed,
// reflectance x sum_j L_j F(x, n -> j). Either way each source's form-factor transfer to
// each product vertex is kept as that source's L_ij for self-shadowing (Gibson 2003 §7.2).
// Cost: O(vertices x emitters) form factors, one volume lookup per vertex, one cube map when
// specular; run only when the product moves (ProductPlacement).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/job_pool.h"
#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/environment_map.h"
#include "shadow/irradiance_volume.h"
#include "shadow/scene_bundle.h"

namespace penumbra::shadow {

struct ProductShadingOptions {
  bool shadeFromVolume = true;  // false: the emitters' form factors even with a volume
  bool specular = true;         // the §5 lobe, for products with a specular reflectance
  uint32_t environmentMapSize = 32;
};

class ProductShading {
 public:
  // `bundle` and `mesh` (the bundle's patch mesh, patchMeshOf) must outlive the shading;
  // `room` bounds the room (sets the environment maps' far plane).
  ProductShading(const SceneBundle& bundle, const scene::PatchMesh& mesh, const scene::Aabb& room,
                 const ProductShadingOptions& options);

  // Shades product `product` placed as `placed` (world space) with world bounds `bounds` and
  // per-vertex `normals` (world space, any positive length: ProductPlacement::normals). Each
  // vertex has the model's own reflectance when it has per-vertex ones (then `placed` must be
  // its mesh), else the product's. Throws std::invalid_argument on a size mismatch.
  void shade(const core::Mesh& placed, std::span<const glm::vec3> normals,
             const scene::Aabb& bounds, uint32_t product);
  // The same with area-weighted vertex normals of `placed` (vertexNormals).
  void shade(const core::Mesh& placed, const scene::Aabb& bounds, uint32_t product);
  // Live lighting (Havran et al. 2005 §4): the same product lit by distant lights k of unit
  // direction towardsLight[k] and RGB power power[k] (radiance x solid angle), unshadowed:
  // per light, diffuse reflectance/pi x power x max(0, n.l) plus, for a product with a
  // specular reflectance, its normalised Phong lobe about the mirrored eye direction,
  // specular x power x (N + 1)/(2 pi) x max(0, r.l)^N — the directional form of the cube-map
  // lobe shade() uses (N the exponent rounded). Each light's term is kept as its transfer
  // (sourceTransfers(), light k in place of source k) for self-shadowing. With `fine` lights
  // (the many faint lights the frame's lights were clustered from, fineTowardsLight and
  // finePower) a glossy product's colour takes Havran 2005 §4.2's two strata: inside the cone
  // about the mirror direction that holds 90% of the lobe's energy, the fine lights; outside
  // it, the frame's lights. radiance() and the transfers stay the frame's lights' (the
  // passes' shares). Throws std::invalid_argument on a size mismatch.
  void shadeFromLights(const core::Mesh& placed, std::span<const glm::vec3> normals,
                       uint32_t product, std::span<const glm::dvec3> towardsLight,
                       std::span<const glm::dvec3> power,
                       std::span<const glm::dvec3> fineTowardsLight = {},
                       std::span<const glm::dvec3> finePower = {});
  // Threads for the per-vertex work (the renderer's pool); null: the calling thread. The
  // bytes do not depend on it.
  void setPool(core::JobPool* pool) { pool_ = pool; }

  // Per vertex of the last shaded product: its colour, and its unshadowed radiance.
  std::span<const core::Rgb8> colours() const { return colours_; }
  std::span<const glm::dvec3> radiance() const { return radiance_; }
  // [source * vertices + v]: the form-factor transfer from source `source` (index into
  // SourceReceiverSets::sources) to vertex v, unshadowed.
  std::span<const glm::dvec3> sourceTransfers() const { return sourceTransfers_; }
  // Changes with every shade or shadeFromLights call (never 0), so that a later stage can
  // tell the radiance and transfers it last read from new ones without comparing them.
  uint64_t generation() const { return generation_; }

 private:
  // The model's per-vertex reflectances, or its one reflectance; checks the sizes.
  std::span<const glm::vec3> reflectancesOf(const ProductModel& model, size_t vertices,
                                            size_t normals) const;

  const SceneBundle& bundle_;
  const scene::PatchMesh& mesh_;
  ProductShadingOptions options_;
  std::vector<uint32_t> emitters_;       // patches with emitted radiance
  std::vector<uint32_t> sourceOfPatch_;  // patch -> source index, or kNoIndex
  ToneInverse toneInverse_;
  raster::ShadedMesh environmentRoom_;  // the room as environment maps draw it
  glm::vec3 eye_{0.0f};                 // the kiosk camera's position (from its matrix)
  float environmentFar_ = 0;            // far plane of the environment maps
  CubeEnvironmentMap environment_;
  std::vector<PhongLobe> lobes_;  // per product
  std::vector<core::Rgb8> colours_;
  std::vector<glm::dvec3> radiance_;
  std::vector<glm::vec3> volumeRadiance_;  // per vertex, from the irradiance volume
  std::vector<glm::dvec3> sourceTransfers_;
  uint64_t generation_ = 0;
  core::JobPool* pool_ = nullptr;
  static constexpr size_t kVertexChunk = 64;
};

}  // namespace penumbra::shadow
