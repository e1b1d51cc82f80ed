// The pass list (Gibson 2003 Fig. 2, §7): one shadow pass per source cluster, in the
// clusters' order (decreasing transfer, §7.1.1). Each pass renders the product's proxy (the
// first fineProxyPasses its fine proxy) into a shadow map from the light frustum fitted around the
// product from the energy-weighted centroid of the cluster's sources (§8 casts from its most
// energetic patch; see clusterCentroid) (shadow/light_frustum.h), of the frame's size or, with
// texelsPerShadowPixel, of its own (shadow/cluster_map_size.h), then masks and subtracts S over
// the receiver triangles that may be shadowed and have something to subtract, S in corner order —
// and over the product's own triangles for self-shadowing (§7.2). A cluster whose light lies inside
// the product's bounding sphere gets no pass (no shadow map can hold the product): counted, so that
// callers can warn. Cost: one frustum fit per cluster, one conservative frustum test per receiver
// triangle; the passes' vectors are reused between frames.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/job_pool.h"
#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/cluster_transfers.h"
#include "shadow/light_frustum.h"
#include "shadow/scene_bundle.h"
#include "shadow/source_clusters.h"

namespace penumbra::shadow {

struct PassListOptions {
  uint32_t shadowMapSize = 256;  // §7.2
  float depthBias = 0.002f;      // light window-depth units
  bool pcf2x2 = true;
  bool cullReceivers = true;      // leave out receivers the frustum cannot shadow
  float objectDepthBias = 0.01f;  // the product's own triangles (§7.2)
  // Distant lights' orthographic maps (buildDirectional) have linear depth: their biases in
  // metres, about what depthBias and objectDepthBias come to at the product from 2 m.
  double directionalBiasMetres = 0.005;
  double directionalObjectBiasMetres = 0.025;
  // The first this many passes draw the product's fine proxy (FrameContent occluder 1)
  // instead of its proxy (occluder 0); 0 when the product has none. They are the clusters
  // with the largest occluded transfer, so a fixed count spends the extra triangles where
  // the proxy's error weighs most, at a cost bounded by count x fine triangles: at the desk
  // corner the bunny's contact error fell 1.020 -> 0.702 levels (p99 17 -> 5) with 16 passes
  // of a 2,500-triangle proxy, against 0.701 / 5 with all 50 passes of its full mesh
  // (docs/accuracy.md). The count holds up to kFineProxyReferencePasses passes and grows in
  // proportion beyond (fineProxyPassesFor).
  uint32_t fineProxyPasses = 0;
  // Per occluder (0 the proxy, 1 the fine proxy): a closed surface wound counter-clockwise
  // from outside (raster/closed_surface.h), whose passes draw only the triangles facing the
  // light — the same map from half the triangles.
  std::array<bool, 2> closedOccluders{};
  // Area-light penumbrae (shadow/area_penumbra.h, spec §7): each point light's pass spreads
  // its shadow edges over the penumbra of its cluster's extent. Maps larger than
  // raster::kMaxAreaPenumbraMapSize keep hard-edged passes. Not for distant lights.
  bool areaPenumbrae = false;
  // A map size per point-light pass from its shadow's footprint on screen
  // (shadow/cluster_map_size.h): this many texels per footprint pixel, at most shadowMapSize
  // (the frame's map); 0: every pass at shadowMapSize. Distant lights keep shadowMapSize.
  double texelsPerShadowPixel = 0;
};

// The pass count at which PassListOptions::fineProxyPasses is stated (issue 15's targets
// are at 50 passes).
inline constexpr uint32_t kFineProxyReferencePasses = 50;

// How many of a frame's `clusters` passes draw the fine proxy: `fineProxyPasses` up to
// kFineProxyReferencePasses clusters, the same share of them beyond, rounded up. A fixed
// count let the fine proxy's share of the light fall as the passes rose — more clusters
// split the same light finer, so the first 16 carried less of it — and the bunny's corner
// got worse from 50 to 82 passes (0.481 -> 0.547 levels, p99 6 -> 8, against 64 spp).
uint32_t fineProxyPassesFor(uint32_t fineProxyPasses, size_t clusters);

class PassList {
 public:
  // `bundle` (its patches and source set: the lights) and `mesh` (the bundle's patch mesh:
  // the receiver triangles) must outlive the list; `room` bounds the room (the frusta's far
  // plane).
  PassList(const SceneBundle& bundle, const scene::PatchMesh& mesh, const scene::Aabb& room);

  // The passes of `selection`'s clusters over `receiverPatches` and the placed `product`
  // (bounds `productBounds`), with the frame's S, into `passes` (reused). Returns the
  // number of clusters left without a pass.
  uint32_t build(const PassListOptions& options, const ClusterSelection& selection,
                 std::span<const uint32_t> receiverPatches, const core::Mesh& product,
                 const scene::Aabb& productBounds, const VertexS& s,
                 std::vector<raster::ShadowPass>& passes);

  // Live lighting (Havran et al. 2005): one pass per distant light k, cast along
  // -towardsLight[k] by an orthographic map fitted around the product (fitDirectionalFrustum),
  // over the receiver patches receiverPatches[lightPatchStart[k], lightPatchStart[k + 1]) and
  // the product, with S column k of `s`. `room` bounds the receivers (the maps' far plane).
  // Throws std::invalid_argument when lightPatchStart does not hold one range per light.
  void buildDirectional(const PassListOptions& options, std::span<const glm::dvec3> towardsLight,
                        std::span<const uint32_t> receiverPatches,
                        std::span<const uint32_t> lightPatchStart, const core::Mesh& product,
                        const scene::Aabb& productBounds, const scene::Aabb& room, const VertexS& s,
                        std::vector<raster::ShadowPass>& passes);

  // Where a cluster's shadow map is cast from: the centroid of its sources' patch centres
  // weighted by their average transfers (`sources`: ClusterSelection::sources); a
  // one-source cluster's own patch centre exactly. If the product's bounding sphere holds
  // that point, build() casts from the representative patch instead.
  glm::dvec3 clusterCentroid(const SourceCluster& cluster, std::span<const uint32_t> sources) const;

  // Per pass of the last build: its cluster (its light, for buildDirectional): the column
  // of S it subtracts.
  std::span<const uint32_t> passCluster() const { return passCluster_; }
  // Threads for filling the passes (the renderer's pool); null: the calling thread. Each
  // pass is filled from its own cluster's S alone, so the bytes do not depend on it.
  void setPool(core::JobPool* pool) { pool_ = pool; }

 private:
  void beginBuild(size_t lights, std::vector<raster::ShadowPass>& passes);
  // `finePasses`: the passes (from the first) that draw the fine proxy.
  // `mapSize`: the pass's shadow map (options.shadowMapSize or its cluster's own).
  void addPass(const PassListOptions& options, const LightFrustum& frustum, size_t column,
               uint32_t mapSize, float depthBias, float objectDepthBias, uint32_t finePasses,
               std::vector<raster::ShadowPass>& passes);
  // Each pass's receiver triangles from patchesOf(its column) (at most mostPatches patches),
  // and the product's triangles.
  template <class PatchesOf>
  void fillPasses(const PassListOptions& options, PatchesOf patchesOf, size_t mostPatches,
                  const core::Mesh& product, const VertexS& s,
                  std::vector<raster::ShadowPass>& passes);
  // `worker`: whose outcode scratch to use (fillPasses sizes one per pool thread).
  void addReceivers(const PassListOptions& options, const glm::dmat4& lightViewProj,
                    std::span<const uint32_t> receiverPatches, const VertexS& s, size_t k,
                    raster::ShadowPass& pass, int worker);
  void addProduct(const core::Mesh& product, const VertexS& s,
                  std::vector<raster::ShadowPass>& passes);

  const SceneBundle& bundle_;
  const scene::PatchMesh& mesh_;
  scene::Aabb room_;
  double farDistance_;
  std::vector<uint32_t> passCluster_;
  std::vector<glm::dmat4> passViewProj_;  // per used pass: the light's frustum (culling)
  core::JobPool* pool_ = nullptr;
  // Per product vertex: the clusters with S there, as bits; per cluster: its triangles, as bits.
  std::vector<uint64_t> vertexClusters_, clusterTriangles_;
  // Per pool thread: each mesh vertex's clipOutcode in the pass being filled (kUnknownCode
  // until a receiver triangle asks), and the vertices to reset after the pass. A cache line
  // each: the vectors' headers change with every push_back, and two threads writing one
  // line made the 2-thread pass list slower than the transforms it saves.
  static constexpr uint8_t kUnknownCode = 0xff;
  struct alignas(64) OutcodeScratch {
    std::vector<uint8_t> codes;
    std::vector<uint32_t> coded;
  };
  std::vector<OutcodeScratch> outcodes_;
};

}  // namespace penumbra::shadow
