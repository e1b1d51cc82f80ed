// The frame's transfers under live lighting (Havran et al. 2005; issue 16): the environment's
// distant lights instead of the captured source patches (cluster_transfers.h). Per frame:
//   1. per light, the receiver patches its shadow of the product can reach: the receiver
//      octree (ShaftHierarchy::receiverNodes) walked against the light's shadow prism —
//      the product's box swept away from the light — and each leaf's patches tested on
//      their own boxes;
//   2. per receiver vertex those patches touch, each light's share of the vertex's direct
//      light, E_k / sum_m E_m with E_k = power_k x max(0, n.l_k) x V_k (lightShares, units of
//      1/65280, per channel), for linear accumulation (docs/pipeline-spec.md §8);
//   3. the same at the product's own vertices from its per-light shading (§7.2
//      self-shadowing; ProductShading::shadeFromLights).
// Reflectance cancels in the shares: a receiver's pixel loses the share of its light that
// the blocked lights carried, whatever the surface's colour. The lights are distant (Havran
// §3): a receiver sees a light unless it is below the receiver's horizon or the room's own
// furniture hides it (the desk hiding the window from the floor beside it:
// static_room_visibility.h, precomputed per receiver vertex when the stage is built), so
// E_k = power_k x max(0, n.l_k) x V_k. A light the desk hides carries no share there, and
// the product's shadow of it is not subtracted from floor the desk already shades.
// Cost: per light an octree walk of O(patches reached + log); per touched vertex O(lights);
// buffers reused between frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/job_pool.h"
#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/cluster_transfers.h"
#include "shadow/receiver_vertex_slots.h"
#include "shadow/scene_bundle.h"
#include "shadow/shaft_hierarchy.h"
#include "shadow/static_room_visibility.h"

namespace penumbra::shadow {

// The frame's distant lights in world space.
struct DistantLights {
  std::span<const glm::dvec3> towardsLight;  // unit, from the scene towards light k
  std::span<const glm::dvec3> power;         // RGB radiance x solid angle
};

class EnvironmentLightTransfers {
 public:
  // `bundle`, `mesh` (patchMeshOf(bundle)) and `hierarchy` (built from them) must outlive
  // the stage.
  EnvironmentLightTransfers(const SceneBundle& bundle, const scene::PatchMesh& mesh,
                            const ShaftHierarchy& hierarchy);

  // The frame's receiver lists and shares for `lights` and the product inside
  // `productBounds`; `product` as ProductShading::shadeFromLights left it (its transfers per
  // light; empty positions: no self-shadowing). `frame` must change from call to call.
  // Throws std::invalid_argument when the lights' spans differ in length.
  void compute(const DistantLights& lights, const scene::Aabb& productBounds, uint32_t frame,
               const ProductLight& product);

  // Per light k, its receiver patches: receiverPatches()[lightPatchStart()[k], [k + 1]).
  std::span<const uint32_t> receiverPatches() const { return lightPatches_; }
  std::span<const uint32_t> lightPatchStart() const { return lightPatchStart_; }
  // Distinct receiver patches over all lights (the frame's receiver count).
  size_t distinctPatches() const { return distinct_.size(); }
  std::span<const uint32_t> frameVertices() const { return slots_.frameVertices(); }
  VertexS s() const {
    return {slots_.receiverVertexOf(), slots_.slots(), receiverS_, productS_, lights_};
  }
  void setPool(core::JobPool* pool);
  // Wall time of the last compute(): the receivers' part (walk and shares), the product's.
  int64_t nsReceivers() const { return nsReceivers_; }
  int64_t nsProduct() const { return nsProduct_; }
  const StaticRoomVisibility& roomVisibility() const { return visibility_; }

 private:
  static constexpr size_t kVertexChunk = 64;
  void findReceivers(const DistantLights& lights, const scene::Aabb& productBounds, uint32_t frame);

  const SceneBundle& bundle_;
  const scene::PatchMesh& mesh_;
  const ShaftHierarchy& hierarchy_;
  ReceiverVertexSlots slots_;
  StaticRoomVisibility visibility_;
  core::JobPool* pool_ = nullptr;
  size_t lights_ = 0;
  int64_t nsReceivers_ = 0, nsProduct_ = 0;
  std::vector<scene::Aabb> patchBounds_;  // per patch: its two triangles' box
  std::vector<uint32_t> patchFrame_;      // per patch: the frame that listed it in distinct_
  std::vector<uint32_t> lightPatches_, lightPatchStart_, distinct_, stack_;
  std::vector<std::vector<glm::dvec3>> rows_{1};       // per worker: one vertex's E_k
  std::vector<StaticRoomVisibility::Lookup> lookups_;  // per light
  std::vector<core::Rgb16> receiverS_;                 // [slot * lights + k]
  std::vector<core::Rgb16> productS_;                  // [v * lights + k]
};

}  // namespace penumbra::shadow
