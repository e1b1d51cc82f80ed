#include "shadow/cluster_transfers.h"

#include <algorithm>

#include "core/clock.h"

#include "shadow/intensity_transfer.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {

ClusterTransfers::ClusterTransfers(const SceneBundle& bundle, const scene::PatchMesh& mesh,
                                   const ClusterTransferOptions& options)
    : bundle_(bundle), mesh_(mesh), options_(options) {
  const RadianceTransfers& t = bundle.transfers;
  receiverVertexOf_.assign(mesh_.positions.size(), kNoIndex);
  for (size_t i = 0; i < t.receiverVertices.size(); ++i) {
    receiverVertexOf_[t.receiverVertices[i]] = static_cast<uint32_t>(i);
  }
  vertexSlot_.assign(t.receiverVertices.size(), 0);
  vertexSlotFrame_.assign(t.receiverVertices.size(), kNoIndex);
}

void ClusterTransfers::compute(std::span<const uint32_t> receiverPatches,
                               const ClusterSelection& selection, uint32_t frame,
                               const ProductLight& product, OcclusionFeedback& feedback) {
  clusters_ = selection.clusters.size();
  gradedVertices_ = 0;
  core::Stopwatch watch;
  gatherFrameVertices(receiverPatches, frame);
  computeReceivers(selection, frame, feedback);
  nsReceivers_ = watch.lapNs();
  computeProduct(selection, product, feedback);
  nsProduct_ = watch.lapNs();
}

// The frame's receiver vertices, each given a slot.
void ClusterTransfers::gatherFrameVertices(std::span<const uint32_t> receiverPatches,
                                           uint32_t frame) {
  frameVertices_.clear();
  for (uint32_t patch : receiverPatches) {
    const uint32_t first = mesh_.patches[patch].firstTriangle;
    for (uint32_t t = first; t < first + 2; ++t) {
      for (int c = 0; c < 3; ++c) {
        const uint32_t rv = receiverVertexOf_[mesh_.indices[3 * size_t(t) + size_t(c)]];
        if (rv == kNoIndex || vertexSlotFrame_[rv] == frame) continue;
        vertexSlotFrame_[rv] = frame;
        vertexSlot_[rv] = static_cast<uint32_t>(frameVertices_.size());
        frameVertices_.push_back(rv);
      }
    }
  }
}

void ClusterTransfers::computeReceivers(const ClusterSelection& selection, uint32_t frame,
                                        OcclusionFeedback& feedback) {
  // Each cluster's transfer to each slot: the sum of its blocked sources' L_ij (§8: the
  // cluster stands for exactly those sources, so all blocked energy is accounted for).
  const RadianceTransfers& tr = bundle_.transfers;
  const size_t clusters = clusters_;
  receiverTransfers_.assign(frameVertices_.size() * clusters, glm::dvec3(0.0));
  feedback.beginShares(frameVertices_.size() * clusters);
  for (size_t k = 0; k < clusters; ++k) {
    const SourceCluster& cl = selection.clusters[k];
    for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
      const uint32_t s = selection.sources[i];
      for (uint32_t e = tr.sourceStart[s]; e < tr.sourceStart[s + 1]; ++e) {
        const uint32_t rv = tr.entryVertex[e];
        if (vertexSlotFrame_[rv] != frame) continue;
        const size_t at = vertexSlot_[rv] * clusters + k;
        receiverTransfers_[at] += glm::dvec3(tr.entryTransfer[e]);
        feedback.addReceiverSource(rv, s, glm::dvec3(tr.entryTransfer[e]), at);
      }
    }
  }
  // §7.1.1, Fig. 4 per receiver vertex, clusters in decreasing transfer (selection order),
  // each in the set of its representative patch's stable id.
  sets_.resize(clusters);
  for (size_t k = 0; k < clusters; ++k) {
    const uint32_t patch = bundle_.sets.sources[selection.clusters[k].representative];
    sets_[k] = static_cast<uint8_t>(sourceSet(options_.setSeed, patch));
  }
  receiverS_.resize(frameVertices_.size() * clusters);
  probes_.resize(frameVertices_.size());
  for (size_t slot = 0; slot < frameVertices_.size(); ++slot) {
    const uint32_t rv = frameVertices_[slot];
    probes_[slot] = bundle_.view.staticMesh.positions[tr.receiverVertices[rv]];
    const glm::dvec3 total(tr.vertexRadiance[rv]);
    const std::span<const glm::dvec3> transfers(receiverTransfers_.data() + slot * clusters,
                                                clusters);
    const std::span<core::Rgb8> s(receiverS_.data() + slot * clusters, clusters);
    const float share = feedback.receiverShare(rv);
    if (options_.gradedTransfers && share >= 0.0f) {
      intensityTransfersForOcclusions(total, transfers,
                                      feedback.clusterShares(slot * clusters, clusters, share),
                                      bundle_.tone, s);
      ++gradedVertices_;
    } else {
      intensityTransfers(total, transfers, sets_, bundle_.tone, s);
    }
  }
}

// The same for the product's own vertices (self-shadowing, §7.2).
void ClusterTransfers::computeProduct(const ClusterSelection& selection,
                                      const ProductLight& product, OcclusionFeedback& feedback) {
  const size_t clusters = clusters_;
  productVertices_ = options_.selfShadowing ? product.positions.size() : 0;
  productTransfers_.assign(productVertices_ * clusters, glm::dvec3(0.0));
  productS_.resize(productVertices_ * clusters);
  feedback.beginShares(productVertices_ * clusters);
  for (size_t k = 0; k < clusters; ++k) {
    const SourceCluster& cl = selection.clusters[k];
    for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
      const uint32_t source = selection.sources[i];
      const glm::dvec3* row = product.sourceTransfers.data() + size_t(source) * productVertices_;
      for (size_t v = 0; v < productVertices_; ++v) {
        productTransfers_[v * clusters + k] += row[v];
        feedback.addProductSource(v, source, row[v], v * clusters + k);
      }
    }
  }
  for (size_t v = 0; v < productVertices_; ++v) {
    const std::span<const glm::dvec3> transfers(productTransfers_.data() + v * clusters, clusters);
    const std::span<core::Rgb8> s(productS_.data() + v * clusters, clusters);
    const float share = feedback.productShare(v);
    if (options_.gradedTransfers && share >= 0.0f) {
      intensityTransfersForOcclusions(product.radiance[v], transfers,
                                      feedback.clusterShares(v * clusters, clusters, share),
                                      bundle_.tone, s);
      ++gradedVertices_;
    } else {
      intensityTransfers(product.radiance[v], transfers, sets_, bundle_.tone, s);
    }
  }
  // Probes: the receiver vertices, then the product's own vertices.
  probes_.resize(frameVertices_.size() + productVertices_);
  std::copy(product.positions.begin(), product.positions.begin() + std::ptrdiff_t(productVertices_),
            probes_.begin() + std::ptrdiff_t(frameVertices_.size()));
}

}  // namespace penumbra::shadow
