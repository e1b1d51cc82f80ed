#include "shadow/receiver_vertex_slots.h"

#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {

ReceiverVertexSlots::ReceiverVertexSlots(const RadianceTransfers& transfers,
                                         const scene::PatchMesh& mesh) {
  receiverVertexOf_.assign(mesh.positions.size(), kNoIndex);
  for (size_t i = 0; i < transfers.receiverVertices.size(); ++i) {
    receiverVertexOf_[transfers.receiverVertices[i]] = static_cast<uint32_t>(i);
  }
  slot_.assign(transfers.receiverVertices.size(), 0);
  slotFrame_.assign(transfers.receiverVertices.size(), kNoIndex);
}

void ReceiverVertexSlots::gather(const scene::PatchMesh& mesh,
                                 std::span<const uint32_t> receiverPatches, uint32_t frame) {
  frameVertices_.clear();
  for (uint32_t patch : receiverPatches) {
    const uint32_t first = mesh.patches[patch].firstTriangle;
    for (uint32_t t = first; t < first + 2; ++t) {
      for (int c = 0; c < 3; ++c) {
        const uint32_t rv = receiverVertexOf_[mesh.indices[3 * size_t(t) + size_t(c)]];
        if (rv == kNoIndex || slotFrame_[rv] == frame) continue;
        slotFrame_[rv] = frame;
        slot_[rv] = static_cast<uint32_t>(frameVertices_.size());
        frameVertices_.push_back(rv);
      }
    }
  }
}

}  // namespace penumbra::shadow
