// The receiver vertices one frame touches, each given a slot (0, 1, ... in the order the
// frame's receiver patches reach them), so that per-frame arrays hold one row per touched
// vertex rather than one per receiver vertex of the room. Shared by the frame's transfer
// stages: the captured sources' (cluster_transfers.h) and the environment lights'
// (environment_light_transfers.h).
// Cost: O(frame's patches) per frame; no allocation once the frame list has reached its
// largest size. A vertex's slot is valid only in the frame that gave it (frame tags).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "scene/patch_mesh.h"
#include "shadow/light_transport.h"

namespace penumbra::shadow {

class ReceiverVertexSlots {
 public:
  // `transfers.receiverVertices` are mesh vertices of `mesh`.
  ReceiverVertexSlots(const RadianceTransfers& transfers, const scene::PatchMesh& mesh);

  // The receiver vertices of `receiverPatches`' triangles, each once, into frameVertices().
  // `frame` must change from call to call.
  void gather(const scene::PatchMesh& mesh, std::span<const uint32_t> receiverPatches,
              uint32_t frame);

  // Mesh vertex -> receiver vertex (index into RadianceTransfers::receiverVertices), or
  // kNoIndex.
  std::span<const uint32_t> receiverVertexOf() const { return receiverVertexOf_; }
  // Receiver vertex -> its slot in the frame that last gathered it (valid when inFrame()).
  std::span<const uint32_t> slots() const { return slot_; }
  bool inFrame(uint32_t receiverVertex, uint32_t frame) const {
    return slotFrame_[receiverVertex] == frame;
  }
  uint32_t slot(uint32_t receiverVertex) const { return slot_[receiverVertex]; }
  // The frame's receiver vertices by slot.
  std::span<const uint32_t> frameVertices() const { return frameVertices_; }

 private:
  std::vector<uint32_t> receiverVertexOf_;
  std::vector<uint32_t> slot_;
  std::vector<uint32_t> slotFrame_;  // receiver vertex -> the frame that gave its slot
  std::vector<uint32_t> frameVertices_;
};

}  // namespace penumbra::shadow
