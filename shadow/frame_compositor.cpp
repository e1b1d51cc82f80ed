#include "shadow/frame_compositor.h"

#include <stdexcept>
#include <string>

#include "core/clock.h"

namespace penumbra::shadow {
namespace {

const scene::Aabb& roomBounds(const ShaftHierarchy& hierarchy) {
  return hierarchy.receiverNodes()[0].bounds;
}

}  // namespace

FrameCompositor::FrameCompositor(const SceneBundle& bundle, const CompositorOptions& options)
    : bundle_(bundle),
      options_(options),
      mesh_(patchMeshOf(bundle)),
      hierarchy_(mesh_, bundle.sets, bundle.transfers, options.shafts),
      placement_(bundle.products),
      shading_(bundle, mesh_, roomBounds(hierarchy_),
               {options.shadeFromVolume, options.specular, options.environmentMapSize}),
      feedback_(bundle.transfers.receiverVertices.size(), bundle.sets.sources.size(),
                options.perClusterShares),
      transfers_(bundle, mesh_,
                 {options.setSeed, options.gradedTransfers, options.selfShadowing,
                  transferKindFor(options.accumulation)}),
      envTransfers_(bundle, mesh_, hierarchy_),
      passList_(bundle, mesh_, roomBounds(hierarchy_)) {
  if (bundle.products.empty()) throw std::invalid_argument("scene bundle has no products");
  if (!options.productFineProxyPasses.empty() &&
      options.productFineProxyPasses.size() != bundle.products.size()) {
    throw std::invalid_argument(
        "fine-proxy passes for " + std::to_string(options.productFineProxyPasses.size()) +
        " products, the bundle has " + std::to_string(bundle.products.size()));
  }
  if (options.accumulation == raster::Accumulation::kLinear) {
    shadeTable_ = linearShadeTable(bundle.tone);
  }
}

void FrameCompositor::compose(const ProductPose& pose, size_t passes, uint32_t frame,
                              raster::FrameContent& out, CompositeStats& stats,
                              std::span<const uint8_t> background) {
  stats = CompositeStats{};
  FrameStages& ns = stats.stages;
  core::Stopwatch watch;
  const PlacementChange change = place(pose);
  ns[FrameStage::kPlacement] = watch.lapNs();
  if (change != PlacementChange::kNone || litShading_) {
    litShading_ = false;
    shading_.shade(placement_.mesh(), placement_.normals(), placement_.bounds(), pose.product);
    stats.shadedVertices = static_cast<uint32_t>(placement_.mesh().positions.size());
  }
  stats.productVertices = static_cast<uint32_t>(placement_.mesh().positions.size());
  ns[FrameStage::kShading] = watch.lapNs();

  blocked_.find(hierarchy_, placement_.bounds(), frame, passes);
  const TraversalResult& traversal = blocked_.traversal;
  stats.occludedSources = static_cast<uint32_t>(traversal.sources.size());
  stats.receiverPatches = static_cast<uint32_t>(traversal.receivers.size());
  stats.shaftsVisited = static_cast<uint32_t>(traversal.shaftsVisited);
  stats.clusters = static_cast<uint32_t>(blocked_.selection.clusters.size());
  ns[FrameStage::kTraversal] = blocked_.nsTraversal;
  ns[FrameStage::kClusters] = blocked_.nsClusters;

  watch.lapNs();
  transfers_.compute(traversal.receivers, blocked_.selection, frame,
                     {placement_.mesh().positions, shading_.radiance(), shading_.sourceTransfers(),
                      shading_.generation()},
                     feedback_);
  stats.transferredVertices = static_cast<uint32_t>(transfers_.productVerticesComputed());
  stats.receiverVertices = static_cast<uint32_t>(transfers_.frameVertices().size());
  stats.gradedVertices = transfers_.gradedVertices();
  ns[FrameStage::kRoomTransfers] = transfers_.nsReceivers();
  ns[FrameStage::kProductTransfers] = transfers_.nsProduct();
  watch.lapNs();

  // The frame description (Fig. 2): background, product, proxy, one pass per cluster.
  frameContent(background, out);
  ns[FrameStage::kFrameContent] = watch.lapNs();
  stats.skippedClusters =
      passList_.build(passListOptions(), blocked_.selection, traversal.receivers, placement_.mesh(),
                      placement_.bounds(), transfers_.s(), out.passes);
  stats.passes = static_cast<uint32_t>(out.passes.size());
  ns[FrameStage::kPassList] = watch.lapNs();
}

PlacementChange FrameCompositor::place(const ProductPose& pose) {
  const PlacementChange change = placement_.place(pose);
  // The feedback sized for a new model in either lighting mode, so that a frame of the other
  // mode finds it so.
  if (change == PlacementChange::kNewModel) {
    feedback_.productPlaced(placement_.mesh().positions.size());
  }
  return change;
}

void FrameCompositor::frameContent(std::span<const uint8_t> background,
                                   raster::FrameContent& out) const {
  if (background.empty()) background = bundle_.background;
  out.background.assign(background.begin(), background.end());
  out.objects.resize(1);
  out.objects[0].mesh = placement_.mesh();
  out.objects[0].colours.assign(shading_.colours().begin(), shading_.colours().end());
  const bool fine = !placement_.fineProxy().indices.empty();
  out.occluders.resize(fine ? 2 : 1);
  out.occluders[0] = placement_.proxy();
  if (fine) out.occluders[1] = placement_.fineProxy();
  out.accumulation = options_.accumulation;
  if (options_.accumulation == raster::Accumulation::kLinear) {
    out.shadeTable.assign(shadeTable_.begin(), shadeTable_.end());
  } else {
    out.shadeTable.clear();
  }
}

void FrameCompositor::composeLit(const ProductPose& pose,
                                 std::span<const envmap::DirectionalLight> lights, uint32_t frame,
                                 raster::FrameContent& out, CompositeStats& stats,
                                 std::span<const uint8_t> background,
                                 std::span<const envmap::DirectionalLight> fineLights) {
  if (options_.accumulation != raster::Accumulation::kLinear) {
    // Fig. 4's S and the graded transfers need the captured transfers L_ij; the lights'
    // shares need nothing but the lights (docs/pipeline-spec.md §8).
    throw std::invalid_argument("live lighting needs linear accumulation");
  }
  stats = CompositeStats{};
  FrameStages& ns = stats.stages;
  core::Stopwatch watch;
  const PlacementChange change = place(pose);
  ns[FrameStage::kPlacement] = watch.lapNs();
  // The lights in world space, split for the stages; the product is shaded again whenever it
  // or the lights moved (the environment camera's frames arrive slower than the kiosk's).
  bool lightsChanged = lights.size() != lightDirections_.size();
  lightDirections_.resize(lights.size());
  lightPowers_.resize(lights.size());
  for (size_t k = 0; k < lights.size(); ++k) {
    lightsChanged = lightsChanged || lightDirections_[k] != lights[k].direction ||
                    lightPowers_[k] != lights[k].power;
    lightDirections_[k] = lights[k].direction;
    lightPowers_[k] = lights[k].power;
  }
  // The fine lights come with the lights (one environment frame): no test of their own.
  if (change != PlacementChange::kNone || lightsChanged || !litShading_) {
    fineDirections_.resize(fineLights.size());
    finePowers_.resize(fineLights.size());
    for (size_t f = 0; f < fineLights.size(); ++f) {
      fineDirections_[f] = fineLights[f].direction;
      finePowers_[f] = fineLights[f].power;
    }
    shading_.shadeFromLights(placement_.mesh(), placement_.normals(), pose.product,
                             lightDirections_, lightPowers_, fineDirections_, finePowers_);
    litShading_ = true;
    stats.shadedVertices = static_cast<uint32_t>(placement_.mesh().positions.size());
  }
  stats.productVertices = static_cast<uint32_t>(placement_.mesh().positions.size());
  ns[FrameStage::kShading] = watch.lapNs();
  const DistantLights distant{lightDirections_, lightPowers_};
  const std::span<const core::Vec3> positions =
      options_.selfShadowing ? std::span<const core::Vec3>(placement_.mesh().positions)
                             : std::span<const core::Vec3>();
  envTransfers_.compute(distant, placement_.bounds(), frame,
                        {positions, shading_.radiance(), shading_.sourceTransfers()});
  stats.transferredVertices = static_cast<uint32_t>(positions.size());
  stats.clusters = static_cast<uint32_t>(lights.size());
  stats.receiverPatches = static_cast<uint32_t>(envTransfers_.distinctPatches());
  stats.receiverVertices = static_cast<uint32_t>(envTransfers_.frameVertices().size());
  ns[FrameStage::kRoomTransfers] = envTransfers_.nsReceivers();
  ns[FrameStage::kProductTransfers] = envTransfers_.nsProduct();
  watch.lapNs();
  frameContent(background, out);
  ns[FrameStage::kFrameContent] = watch.lapNs();
  passList_.buildDirectional(passListOptions(), lightDirections_, envTransfers_.receiverPatches(),
                             envTransfers_.lightPatchStart(), placement_.mesh(),
                             placement_.bounds(), roomBounds(hierarchy_), envTransfers_.s(),
                             out.passes);
  stats.passes = static_cast<uint32_t>(out.passes.size());
  stats.skippedClusters = stats.clusters - stats.passes;
  ns[FrameStage::kPassList] = watch.lapNs();
}

void FrameCompositor::observe(std::span<const uint8_t> masks) {
  // Light shares do not depend on occlusion, and the product's transfers that observing
  // would weigh by are not kept under them (ClusterTransfers::productTransfers).
  if (options_.accumulation == raster::Accumulation::kLinear) return;
  feedback_.observe(masks, {passList_.passCluster(), &blocked_.selection,
                            transfers_.frameVertices(), transfers_.receiverTransfers(),
                            transfers_.productTransfers(), transfers_.productVertices()});
}

void FrameCompositor::setShadowMapSize(uint32_t size) {
  if (size < 16 || size > raster::kMaxShadowMapSize || size % 16 != 0) {
    throw std::invalid_argument("shadow map size " + std::to_string(size) +
                                " is not a multiple of 16 in 16..4096");
  }
  options_.shadowMapSize = size;
}

void FrameCompositor::productModelChanged(uint32_t product) {
  placement_.modelChanged(product);
}

PassListOptions FrameCompositor::passListOptions() const {
  PassListOptions o;
  o.shadowMapSize = options_.shadowMapSize;
  o.depthBias = options_.depthBias;
  o.pcf2x2 = options_.pcf2x2;
  o.cullReceivers = options_.cullReceivers;
  o.objectDepthBias = options_.objectDepthBias;
  o.fineProxyPasses =
      placement_.fineProxy().indices.empty()
          ? 0
          : fineProxyPassesOf(options_.fineProxyPasses, options_.productFineProxyPasses,
                              placement_.pose().product);
  o.areaPenumbrae = options_.areaPenumbrae;
  o.texelsPerShadowPixel = options_.texelsPerShadowPixel;
  if (options_.cullClosedProxies) {
    o.closedOccluders = {placement_.proxyClosed(), placement_.fineProxyClosed()};
  }
  return o;
}

}  // namespace penumbra::shadow
