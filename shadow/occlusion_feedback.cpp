#include "shadow/occlusion_feedback.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra::shadow {

OcclusionFeedback::OcclusionFeedback(size_t receiverVertices, size_t sources, bool perClusterShares)
    : sources_(sources),
      perClusterShares_(perClusterShares),
      occlusion_(receiverVertices, -1.0f),
      sourceOccluded_(receiverVertices * sources, -1) {}

void OcclusionFeedback::productPlaced(size_t vertices) {
  productOcclusion_.assign(vertices, -1.0f);
  productSourceOccluded_.assign(vertices * sources_, -1);
}

void OcclusionFeedback::clusterShares(size_t first, float fallback, std::span<double> out) const {
  std::fill(out.begin(), out.end(), double(fallback));
  if (!perClusterShares_) return;
  for (size_t k = 0; k < out.size(); ++k) {
    const double seen = clusterSeen_[first + k];
    if (seen > 0) out[k] = std::min(1.0, clusterOccluded_[first + k] / seen);
  }
}

void OcclusionFeedback::observe(std::span<const uint8_t> masks, const ObservedFrame& frame) {
  const size_t passes = frame.passCluster.size();
  const size_t receiverProbes = frame.receiverVertices.size();
  if (masks.size() != (receiverProbes + frame.productVertices) * passes) {
    throw std::invalid_argument("observe: masks do not match the last composed frame");
  }
  const ClusterSelection& selection = *frame.selection;
  const size_t clusters = selection.clusters.size();
  // The transfer-weighted share of a probe's blocked light that was really occluded, summed
  // in pass order; -1 when nothing reaches it. `transfers` are the probe's per-cluster ones.
  // Also which sources each pass's mask occluded at the probe, into `seen` (its row of
  // sourceOccluded_ or productSourceOccluded_); sources without a pass are not seen.
  auto observeProbe = [&](size_t probe, const glm::dvec3* transfers, int8_t* seen) {
    std::fill(seen, seen + sources_, int8_t{-1});
    double blocked = 0, total = 0;
    for (size_t k = 0; k < passes; ++k) {
      const glm::dvec3& t = transfers[frame.passCluster[k]];
      const double weight = transferWeight(t);
      const bool occluded = masks[probe * passes + k] != 0;
      total += weight;
      blocked += occluded ? weight : 0.0;
      const SourceCluster& cl = selection.clusters[frame.passCluster[k]];
      for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
        seen[selection.sources[i]] = occluded ? 1 : 0;
      }
    }
    return total > 0 ? static_cast<float>(blocked / total) : -1.0f;
  };
  // Each probe writes its own share and its own row of seen sources: chunks on the pool.
  core::forEachChunk(pool_, receiverProbes, kProbeChunk, [&](size_t begin, size_t end, int) {
    for (size_t slot = begin; slot < end; ++slot) {
      const uint32_t rv = frame.receiverVertices[slot];
      occlusion_[rv] = observeProbe(slot, frame.receiverTransfers.data() + slot * clusters,
                                    sourceOccluded_.data() + size_t(rv) * sources_);
    }
  });
  core::forEachChunk(pool_, frame.productVertices, kProbeChunk, [&](size_t begin, size_t end, int) {
    for (size_t v = begin; v < end; ++v) {
      productOcclusion_[v] =
          observeProbe(receiverProbes + v, frame.productTransfers.data() + v * clusters,
                       productSourceOccluded_.data() + v * sources_);
    }
  });
}

}  // namespace penumbra::shadow
