// The per-frame pipeline of Gibson 2003 (design §1, "Per frame"): place the product, find
// the light it blocks (§6.1 shaft traversal), group the blocked sources into n clusters
// (§8), turn their radiance transfers into 8-bit intensity transfers (§7.1.1, Fig. 4),
// and describe the frame for the rasterizer (raster::FrameContent: background, shaded
// product, occluder proxy, one pass per cluster, Fig. 2).
//
// Cost per frame: traversal and selection (tens of microseconds), one sparse sum per
// cluster over its sources' transfers to the frame's receiver vertices, Fig. 4 per
// receiver vertex. Buffers are reused; after the first frames compose() does not
// allocate unless the receiver set grows.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/environment_map.h"
#include "shadow/irradiance_volume.h"
#include "shadow/scene_bundle.h"
#include "shadow/shaft_hierarchy.h"
#include "shadow/source_clusters.h"

namespace penumbra::shadow {

struct CompositorOptions {
  uint32_t shadowMapSize = 256;  // Gibson 2003 §7.2
  float depthBias = 0.002f;      // light window-depth units
  bool pcf2x2 = true;
  uint64_t setSeed = 1;  // Fig. 4's set assignment (stable per source patch)
  // Beyond Fig. 4 (docs/fig3.md): where the previous frame measured how much of a receiver
  // vertex's light the product blocked (observe()), take its intensity transfers at that
  // occluded share q (intensityTransfersForOcclusion); elsewhere Fig. 4's 50/50 sets.
  bool gradedTransfers = true;
  // With graded transfers: take one occluded share per cluster — the share of its sources
  // the previous frame saw occluded at that vertex (intensityTransfersForOcclusions) —
  // instead of one share for all clusters, so that where the same clusters are occluded
  // again their drops telescope exactly (penumbrae, docs/accuracy.md).
  bool perClusterShares = true;
  // Self-shadowing (Gibson 2003 §7.2): the product's own vertices receive every pass too,
  // with intensity transfers from the cluster's sources to them, and a larger bias: the
  // proxy in the shadow map only approximates the product's surface.
  bool selfShadowing = true;
  // Leave out of a pass the receivers its light frustum cannot shadow (same bytes, less work).
  bool cullReceivers = true;
  float objectDepthBias = 0.01f;
  // How the frame sums its passes (docs/pipeline-spec.md §8): fixed8_8 keeps 1/256 levels
  // per pass and rounds each pixel's sum once, so the many faint passes of a high pass count
  // do not drift (Gibson 2003 §10; docs/failure-regimes.md). kU8 is Gibson 2003 Fig. 2's
  // per-pass 8-bit blending.
  raster::Accumulation accumulation = raster::Accumulation::kFixed8_8;
  // Shade the product from the bundle's irradiance volume when it has one (Gibson &
  // Chalmers 2003 §5); false: the emitters' form factors (the pre-volume shading).
  bool shadeFromVolume = true;
  // Specular term (§5, Fig. 9) for products with a specular reflectance, from a cube map
  // of this many pixels per side rendered at the product's centre whenever it moves.
  bool specular = true;
  uint32_t environmentMapSize = 32;
  ShaftBuildOptions shafts;
};

struct CompositeStats {
  uint32_t occludedSources = 0, receiverPatches = 0, clusters = 0, passes = 0;
  uint32_t shaftsVisited = 0, receiverVertices = 0;
  uint32_t gradedVertices = 0;  // receiver and product vertices whose S used a measured share
  // Clusters left without a pass because their light lies inside the product's bounding
  // sphere (fitLightFrustum): their shadow is missing. Callers should warn (a product larger
  // than the room loses every shadow this way).
  uint32_t skippedClusters = 0;
  double msTraversal = 0, msClusters = 0, msTransfers = 0, msObject = 0;
};

class FrameCompositor {
 public:
  // Builds the shaft hierarchy from the bundle (deterministic). Throws std::invalid_argument
  // for inconsistent bundles.
  FrameCompositor(const SceneBundle& bundle, const CompositorOptions& options);

  // The frame for `pose` with at most `passes` clusters, into `out` (reused between
  // frames). `frame` must change from call to call (the §6.1 frame tags).
  void compose(const ProductPose& pose, size_t passes, uint32_t frame, raster::FrameContent& out,
               CompositeStats& stats);

  // World positions of the last composed frame's receiver vertices, then of the product's
  // own vertices (from index objectProbesFrom()): pass them to raster::Renderer::render()
  // as probes, then hand the masks to observe().
  std::span<const core::Vec3> probes() const { return probes_; }
  size_t objectProbesFrom() const { return frameVertices_.size(); }
  // Records, per receiver vertex of the last composed frame, the share of its blocked
  // transfer that the rendered passes really occluded, and which sources they occluded
  // there (masks as Renderer::render fills them).
  void observe(std::span<const uint8_t> masks);

  // The shadow-map size of the next frames (the controller's ladder, Gibson 2003 §8: fewer
  // texels before fewer passes). A multiple of 16 in 16..4096.
  void setShadowMapSize(uint32_t size);
  // Product `product`'s model in the bundle was replaced (kiosk product files): when it is
  // the placed one, the next compose() places and shades it afresh.
  void productModelChanged(uint32_t product);

  const ShaftHierarchy& hierarchy() const { return hierarchy_; }
  const raster::StaticView& view() const { return bundle_.view; }

 private:
  void placeProduct(const ProductPose& pose);
  void shadeProduct();
  void seenShare(int8_t state, const glm::dvec3& transfer, size_t at);
  std::span<const double> clusterShares(size_t first, size_t clusters, float fallback);

  const SceneBundle& bundle_;
  CompositorOptions options_;
  scene::PatchMesh mesh_;
  ShaftHierarchy hierarchy_;
  std::vector<uint32_t> receiverVertexOf_;  // mesh vertex -> receiver vertex, or kNoIndex
  std::vector<uint32_t> sourceOfPatch_;     // patch -> source index, or kNoIndex
  std::vector<uint32_t> emitters_;          // patches with emitted radiance

  // Per-frame state, reused.
  TraversalResult traversal_;
  ClusterSelection selection_;
  ProductPose placedPose_{~0u, 0, 0, 0};
  core::Mesh placedMesh_, placedProxy_;
  std::vector<core::Rgb8> productColours_;
  std::vector<glm::dvec3> productRadiance_;  // per vertex: unshadowed radiance
  std::vector<glm::vec3> volumeRadiance_;    // per vertex, from the irradiance volume
  ToneLut toneLut_;
  ToneInverse toneInverse_;
  raster::ShadedMesh environmentRoom_;  // the room as environment maps draw it
  glm::vec3 eye_{0.0f};                 // the kiosk camera's position (from its matrix)
  CubeEnvironmentMap environment_;
  std::vector<PhongLobe> lobes_;             // per product
  std::vector<glm::dvec3> productTransfer_;  // [source * vertices + v]: from each source
  std::vector<glm::dvec3> productCluster_;   // [v * clusters + k]
  std::vector<core::Rgb8> productS_;         // [v * clusters + k]
  scene::Aabb productBounds_;
  std::vector<uint32_t> frameVertices_;  // receiver vertices touched this frame
  std::vector<uint32_t> vertexSlot_;     // receiver vertex -> slot in frameVertices_
  std::vector<uint32_t> vertexSlotFrame_;
  std::vector<glm::dvec3> clusterTransfer_;  // [slot * clusters + k]
  std::vector<core::Rgb8> clusterS_;         // [slot * clusters + k]
  std::vector<glm::dvec3> transfersScratch_;
  std::vector<uint8_t> setsScratch_;
  std::vector<core::Rgb8> sScratch_;
  std::vector<uint32_t> passCluster_;  // emitted pass -> cluster
  std::vector<core::Vec3> probes_;     // per slot
  std::vector<float> occlusion_;       // per receiver vertex: measured share, or < 0
  // [receiver vertex * sources + source]: 1 occluded, 0 not, as the last observed frame saw
  // it at that vertex; -1 not seen. The same for the product's vertices.
  std::vector<int8_t> sourceOccluded_;
  std::vector<int8_t> productSourceOccluded_;
  // Per slot (or product vertex) and cluster: luminance of the transfer from sources seen
  // by the last observation, and of the part seen occluded.
  std::vector<double> clusterSeen_, clusterOccluded_;
  std::vector<double> sharesScratch_;
  std::vector<float> productOcclusion_;  // per product vertex: measured share, or < 0
};

}  // namespace penumbra::shadow
