// The precomputed light transport of a static room (Gibson 2003 §4–5): which patches are
// sources and receivers, and the radiance every source patch sends to every receiver
// vertex. Built once per showroom (lighting/radiance_transfer.h), stored in the scene
// bundle, read by the shaft hierarchy (§6), the source clusters (§8) and the intensity
// transfers (§7.1.1) every frame.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::shadow {

// §4. Patch indices refer to scene::PatchMesh::patches.
struct SourceReceiverSets {
  // Patches with non-zero emitted radiance, brightest first, that hold `powerShare` of the
  // total emitted power (power = radiance luminance x area).
  std::vector<uint32_t> sources;
  // Patches visible from the calibrated camera (at least one pixel of the static depth).
  std::vector<uint32_t> receivers;
  double powerShare = 0.7;
};

// §5. Receiver vertices are the mesh vertices of receiver patches, each listed once.
// Transfers are stored sparsely by source (compressed rows): only pairs whose transfer
// exceeds a small threshold are kept.
struct RadianceTransfers {
  std::vector<uint32_t> receiverVertices;  // mesh vertex index of receiver vertex i
  // L_i: radiance leaving receiver vertex i towards the camera with every source visible
  // (all emitting patches, not only the source set, plus the vertex's own emission).
  std::vector<glm::vec3> vertexRadiance;
  // Source s (index into SourceReceiverSets::sources) has entries
  // [sourceStart[s], sourceStart[s + 1]) of entryVertex / entryTransfer.
  std::vector<uint32_t> sourceStart;
  std::vector<uint32_t> entryVertex;     // receiver vertex index i
  std::vector<glm::vec3> entryTransfer;  // L_ij = reflectance x form factor x visibility x L_j
  // Mean over receiver vertices of L_ij's luminance, per source: the order of §7.1.1.
  std::vector<float> sourceAverage;

  size_t sourceCount() const { return sourceStart.empty() ? 0 : sourceStart.size() - 1; }
};

}  // namespace penumbra::shadow
