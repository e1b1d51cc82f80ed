// Occlusion feedback (beyond Gibson 2003 Fig. 4, docs/fig3.md): after a frame is rendered,
// the renderer's occlusion masks at the probes (the frame's receiver vertices, then the
// product's own vertices) say how much of each vertex's blocked light the passes really
// occluded, and which sources they occluded there. The next frame takes its intensity
// transfers at those measured shares (intensityTransfersForOcclusion(s)) instead of Fig. 4's
// 50/50 sets, so where the same clusters are occluded again their drops telescope exactly.
//
// State per receiver vertex and per product vertex: one measured share (< 0: not measured)
// and one occluded/not/unseen flag per source. Per frame: the seen and occluded luminance
// of each (vertex, cluster) entry, summed while the transfers stage adds up the clusters'
// transfers (addReceiverSource / addProductSource), read back by clusterShares().
// Cost: observe() is O(probes x (passes + sources)); no allocation after the first frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/colour.h"
#include "core/job_pool.h"
#include "shadow/source_clusters.h"

namespace penumbra::shadow {

// Weight of a transfer when shares of light are measured (Rec. 709 luminance, in double).
inline double transferWeight(const glm::dvec3& t) {
  return core::luminance(t);
}

// What observe() needs of the frame it measures: its passes, clusters and per-probe
// cluster transfers, as the transfers and pass-list stages left them.
struct ObservedFrame {
  std::span<const uint32_t> passCluster;  // pass -> cluster (clusters without a pass omitted)
  const ClusterSelection* selection = nullptr;
  std::span<const uint32_t> receiverVertices;     // per receiver probe: its receiver vertex
  std::span<const glm::dvec3> receiverTransfers;  // [probe * clusters + k]
  std::span<const glm::dvec3> productTransfers;   // [product vertex * clusters + k]
  size_t productVertices = 0;                     // product probes after the receiver ones
};

class OcclusionFeedback {
 public:
  // `perClusterShares` off: clusterShares() gives every cluster the vertex's one share.
  OcclusionFeedback(size_t receiverVertices, size_t sources, bool perClusterShares);

  // A new product model is placed: nothing is measured on its `vertices` yet.
  void productPlaced(size_t vertices);

  // The share of receiver vertex `rv`'s (product vertex `v`'s) blocked light that the last
  // observed frame occluded; < 0 when not measured.
  float receiverShare(uint32_t rv) const { return occlusion_[rv]; }
  float productShare(size_t v) const { return productOcclusion_[v]; }

  // Starts summing `entries` (vertex, cluster) entries of seen and occluded luminance.
  void beginShares(size_t entries) {
    clusterSeen_.assign(entries, 0.0);
    clusterOccluded_.assign(entries, 0.0);
  }
  // Adds source `source`'s transfer to receiver vertex `rv` (product vertex `v`) to entry
  // `at` when the last observation saw that source there.
  void addReceiverSource(uint32_t rv, uint32_t source, const glm::dvec3& transfer, size_t at) {
    seenShare(sourceOccluded_[size_t(rv) * sources_ + source], transfer, at);
  }
  void addProductSource(size_t v, uint32_t source, const glm::dvec3& transfer, size_t at) {
    seenShare(productSourceOccluded_[v * sources_ + source], transfer, at);
  }
  // The expected occluded share of each of out.size() clusters from entry `first` on, into
  // `out`: the seen sources' occluded share, or `fallback` (the vertex's one measured share)
  // for a cluster none of whose sources was seen, or for all with perClusterShares off.
  // Reads only: threads may call it for different entries at once.
  void clusterShares(size_t first, float fallback, std::span<double> out) const;

  // Records, per probe of `frame`, the transfer-weighted share of its blocked light that the
  // passes occluded (masks[probe * passes + k] != 0, as raster::Renderer::render fills them)
  // and which sources they occluded there. Throws std::invalid_argument when the masks do
  // not match the frame.
  void observe(std::span<const uint8_t> masks, const ObservedFrame& frame);
  // Threads for observe()'s probes (the renderer's pool); null: the calling thread.
  void setPool(core::JobPool* pool) { pool_ = pool; }

 private:
  // Adds one source's transfer to entry `at`'s seen (and occluded) luminance when the last
  // observation saw that source at this vertex (`state` 0 or 1).
  void seenShare(int8_t state, const glm::dvec3& transfer, size_t at) {
    if (state < 0) return;
    const double weight = transferWeight(transfer);
    clusterSeen_[at] += weight;
    if (state > 0) clusterOccluded_[at] += weight;
  }

  size_t sources_;
  bool perClusterShares_;
  std::vector<float> occlusion_;         // per receiver vertex: measured share, or < 0
  std::vector<float> productOcclusion_;  // per product vertex: measured share, or < 0
  // [vertex * sources + source]: 1 occluded, 0 not, as the last observed frame saw it at
  // that vertex; -1 not seen.
  std::vector<int8_t> sourceOccluded_;
  std::vector<int8_t> productSourceOccluded_;
  std::vector<double> clusterSeen_, clusterOccluded_;  // per (vertex, cluster) entry
  core::JobPool* pool_ = nullptr;
  static constexpr size_t kProbeChunk = 64;
};

}  // namespace penumbra::shadow
