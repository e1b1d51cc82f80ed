// The per-frame pipeline of Gibson 2003 (design §1, "Per frame"), as a sequence of stages,
// each in its own file pair:
//   1. shadow/product_placement  the product moved to its pose; its bounds
//   2. shadow/product_shading    its colours through T() (Gibson & Chalmers 2003 §5) and
//                                each source's transfer to its vertices (§7.2)
//   3. shadow/blocked_light      §6.1 shaft traversal with the product's box, §8 clusters
//   4. shadow/cluster_transfers  each cluster's transfer to each receiver and product
//                                vertex, 8-bit intensity transfers S (§7.1.1, Fig. 4)
//   5. shadow/pass_list          one shadow pass per cluster (Fig. 2, §7)
//   6. shadow/occlusion_feedback after rendering: the occluded shares the next frame's S
//                                are taken at (docs/fig3.md)
// FrameCompositor owns the stages and runs 1-5 in compose(), 6 in observe(); the result is
// a raster::FrameContent (background, shaded product, occluder proxy, the passes).
// shadow/frame_loop.h runs compose -> render -> observe, frame after frame.
//
// Cost per frame: traversal and selection (tens of microseconds), one sparse sum per
// cluster over its sources' transfers to the frame's receiver vertices, Fig. 4 per
// receiver vertex. Buffers are reused; after the first frames compose() does not
// allocate unless the receiver set grows.
#pragma once

#include <cstdint>
#include <vector>

#include "envmap/directional_light.h"
#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/blocked_light.h"
#include "shadow/cluster_transfers.h"
#include "shadow/environment_light_transfers.h"
#include "shadow/frame_stages.h"
#include "shadow/occlusion_feedback.h"
#include "shadow/pass_list.h"
#include "shadow/product_placement.h"
#include "shadow/product_shading.h"
#include "shadow/scene_bundle.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {

struct CompositorOptions {
  uint32_t shadowMapSize = 256;  // Gibson 2003 §7.2
  float depthBias = 0.002f;      // light window-depth units
  bool pcf2x2 = true;
  // Passes that draw the product's fine proxy when its model has one
  // (PassListOptions::fineProxyPasses).
  uint32_t fineProxyPasses = 16;
  // Empty, or one per product in place of fineProxyPasses (RenderSettings::
  // productFineProxyPasses).
  std::vector<uint32_t> productFineProxyPasses;
  // Draw a closed proxy's front faces only (PassListOptions::closedOccluders): the same
  // frames, half the shadow-map triangles. False draws every triangle (the A/B of tests).
  bool cullClosedProxies = true;
  // Each point light's pass spreads its shadow edges over its cluster's penumbra
  // (PassListOptions::areaPenumbrae, shadow/area_penumbra.h). Off: Gibson 2003's hard-edged
  // passes (2x2 PCF), the A/B of docs/accuracy.md.
  bool areaPenumbrae = true;
  // Each point-light pass's map from its shadow's footprint on screen, this many texels per
  // pixel, at most shadowMapSize (PassListOptions::texelsPerShadowPixel); 0: all at
  // shadowMapSize.
  double texelsPerShadowPixel = 0;
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
  // How the frame sums its passes (docs/pipeline-spec.md §8): linear (the default) sums
  // each cluster's share of the pixel's light and scales the light once through the shade
  // table, exact wherever the shares are and with no measured occlusion needed; fixed8_8
  // subtracts 8.8 S graded at the measured occlusion, rounding each pixel's sum once, so
  // faint passes do not drift (Gibson 2003 §10; docs/failure-regimes.md); kU8 is Gibson
  // 2003 Fig. 2's per-pass 8-bit blending.
  raster::Accumulation accumulation = raster::Accumulation::kLinear;
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
  // The placed product's vertices; how many of them were shaded this frame (all of them when
  // it moved or its light changed, else 0) and how many had their transfers and S worked out
  // (ClusterTransfers::productVerticesComputed): the product's share of the frame's work, for
  // the simulated board's cost model (frame_cost_model.h).
  uint32_t productVertices = 0, shadedVertices = 0, transferredVertices = 0;
  // Wall time of compose()'s stages (placement to pass list); the others stay 0.
  FrameStages stages;
};

class FrameCompositor {
 public:
  // Builds the shaft hierarchy from the bundle (deterministic). Throws std::invalid_argument
  // for inconsistent bundles.
  FrameCompositor(const SceneBundle& bundle, const CompositorOptions& options);

  // The frame for `pose` with at most `passes` clusters, into `out` (reused between
  // frames). `frame` must change from call to call (the §6.1 frame tags). The background is
  // `background` (RGBA8 at the view's size, the kiosk's camera frame) or, when empty, the
  // bundle's photograph.
  void compose(const ProductPose& pose, size_t passes, uint32_t frame, raster::FrameContent& out,
               CompositeStats& stats, std::span<const uint8_t> background = {});

  // Live lighting (Havran et al. 2005; issue 16): the same frame lit by the environment's
  // distant lights instead of the captured sources — `lights` in world space (unit
  // directions towards them, RGB powers in the room camera's radiance units), one pass each,
  // so the caller sets the pass count by the number of lights. The product is shaded by the
  // lights (ProductShading::shadeFromLights), each light's share of each receiver's light
  // comes from environment_light_transfers.h, and the passes are cast by orthographic maps
  // (PassList::buildDirectional); the compositing is the same. Needs linear accumulation
  // (std::invalid_argument otherwise): nothing to observe afterwards. `fineLights`, the many
  // faint lights `lights` were clustered from (world space too), refine a glossy product's
  // highlight (Havran 2005 §4.2, ProductShading::shadeFromLights); empty: none.
  void composeLit(const ProductPose& pose, std::span<const envmap::DirectionalLight> lights,
                  uint32_t frame, raster::FrameContent& out, CompositeStats& stats,
                  std::span<const uint8_t> background = {},
                  std::span<const envmap::DirectionalLight> fineLights = {});

  // World positions of the last composed frame's receiver vertices, then of the product's
  // own vertices (from index objectProbesFrom()): pass them to raster::Renderer::render()
  // as probes, then hand the masks to observe().
  std::span<const core::Vec3> probes() const { return transfers_.probes(); }
  size_t objectProbesFrom() const { return transfers_.frameVertices().size(); }
  // Whether the next frames' transfers depend on the occlusion observe() measures: graded
  // transfers of S (u8, fixed8_8). Linear accumulation's light shares do not.
  bool measuresOcclusion() const {
    return options_.gradedTransfers && options_.accumulation != raster::Accumulation::kLinear;
  }
  // Records, per receiver vertex of the last composed frame, the share of its blocked
  // transfer that the rendered passes really occluded, and which sources they occluded
  // there (masks as Renderer::render fills them). Nothing under linear accumulation (see
  // measuresOcclusion).
  void observe(std::span<const uint8_t> masks);

  // Threads for the per-vertex stages (the renderer's pool, FrameLoop); null: the calling
  // thread. The frame's bytes do not depend on it.
  void setPool(core::JobPool* pool) {
    shading_.setPool(pool);
    transfers_.setPool(pool);
    envTransfers_.setPool(pool);
    passList_.setPool(pool);
    feedback_.setPool(pool);
  }
  // The shadow-map size of the next frames (the controller's ladder, Gibson 2003 §8: fewer
  // texels before fewer passes). A multiple of 16 in 16..4096.
  void setShadowMapSize(uint32_t size);
  // Product `product`'s model in the bundle was replaced (kiosk product files): when it is
  // the placed one, the next compose() places and shades it afresh.
  void productModelChanged(uint32_t product);

  const ShaftHierarchy& hierarchy() const { return hierarchy_; }
  const raster::StaticView& view() const { return bundle_.view; }

 private:
  PassListOptions passListOptions() const;
  // The product at `pose` (ProductPlacement), the occlusion feedback sized for a new model.
  PlacementChange place(const ProductPose& pose);
  // Background, the shaded product, its proxy and the shade table into `out`.
  void frameContent(std::span<const uint8_t> background, raster::FrameContent& out) const;

  const SceneBundle& bundle_;
  CompositorOptions options_;
  scene::PatchMesh mesh_;
  ShaftHierarchy hierarchy_;
  // The stages: compose() runs placement to pass list, the transfers reading the feedback's
  // shares; observe() records the next ones.
  ProductPlacement placement_;
  ProductShading shading_;
  BlockedLight blocked_;
  OcclusionFeedback feedback_;
  ClusterTransfers transfers_;
  EnvironmentLightTransfers envTransfers_;                 // composeLit()'s instead of transfers_
  std::vector<glm::dvec3> lightDirections_, lightPowers_;  // composeLit()'s last lights
  std::vector<glm::dvec3> fineDirections_, finePowers_;    // and its fine lights
  bool litShading_ = false;          // the product's colours are the lights' (composeLit())
  std::vector<uint8_t> shadeTable_;  // linear accumulation's (raster::FrameContent::shadeTable)
  PassList passList_;
};

}  // namespace penumbra::shadow
