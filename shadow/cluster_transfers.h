// The frame's transfers (design §1, per frame step 6): each cluster's radiance transfer to
// each receiver vertex the frame touches, and to each of the product's own vertices — the
// sum of its blocked sources' L_ij, so all blocked energy is accounted for (Gibson 2003
// §8) — turned into 8-bit intensity transfers S per vertex and cluster (§7.1.1, Fig. 4:
// shadow/intensity_transfer.h). Where the occlusion feedback measured a share the last frame
// (shadow/occlusion_feedback.h), S is taken at that share instead of Fig. 4's two sets.
// Also the probes at which the renderer measures the next feedback: the receiver vertices,
// then the product's vertices.
// Cost: one sparse sum per cluster over its sources' transfer rows, one Fig. 4 per vertex.
// Buffers are reused; no allocation unless the receiver set grows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/job_pool.h"
#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/intensity_transfer.h"
#include "shadow/light_share_kernels.h"
#include "shadow/occlusion_feedback.h"
#include "shadow/receiver_vertex_slots.h"
#include "shadow/scene_bundle.h"
#include "shadow/source_clusters.h"

namespace penumbra::shadow {

struct ClusterTransferOptions {
  uint64_t setSeed = 1;         // Fig. 4's set assignment (stable per source patch)
  bool gradedTransfers = true;  // take S at the measured shares where there are some
  bool selfShadowing = true;    // the product's own vertices too (§7.2)
  // What the passes carry per vertex and cluster (intensity_transfer.h): S in whole levels
  // (u8 accumulation), S in 8.8 levels (fixed8_8), or the cluster's share of the vertex's
  // light (linear, which needs neither Fig. 4 nor the measured shares).
  TransferKind kind = TransferKind::kLightShares;
};

// The product as the transfers see it: its placed vertices, their unshadowed radiance and
// each source's unshadowed transfer to them (ProductShading).
struct ProductLight {
  std::span<const core::Vec3> positions;
  std::span<const glm::dvec3> radiance;         // per vertex
  std::span<const glm::dvec3> sourceTransfers;  // [source * vertices + v]
  // ProductShading::generation() of the three, or 0 (unknown): with light shares, a call
  // with the last call's generation and cluster sources keeps the last S.
  uint64_t generation = 0;
};

// The frame's S per vertex and cluster, as the pass list reads them.
struct VertexS {
  std::span<const uint32_t> receiverVertexOf;  // mesh vertex -> receiver vertex, or kNoIndex
  std::span<const uint32_t> vertexSlot;        // receiver vertex -> slot (this frame's only)
  std::span<const core::Rgb16> receiverS;      // [slot * clusters + k], 8.8 (TransferKind)
  std::span<const core::Rgb16> productS;       // [v * clusters + k]; empty: no self-shadowing
  size_t clusters = 0;
};

class ClusterTransfers {
 public:
  // `bundle` and `mesh` (the bundle's patch mesh, patchMeshOf) must outlive the stage.
  ClusterTransfers(const SceneBundle& bundle, const scene::PatchMesh& mesh,
                   const ClusterTransferOptions& options);

  // Transfers and S of `selection`'s clusters to the vertices of `receiverPatches` (the
  // traversal's receiver list) and to the product's vertices. `frame` must change from call
  // to call. Sums the feedback's seen shares on the way (OcclusionFeedback::beginShares).
  void compute(std::span<const uint32_t> receiverPatches, const ClusterSelection& selection,
               uint32_t frame, const ProductLight& product, OcclusionFeedback& feedback);

  size_t clusters() const { return clusters_; }
  // The frame's receiver vertices (indices into RadianceTransfers::receiverVertices), one
  // slot each, in the order the receiver patches reached them.
  std::span<const uint32_t> frameVertices() const { return slots_.frameVertices(); }
  std::span<const glm::dvec3> receiverTransfers() const {  // [slot * clusters + k]
    return receiverTransfers_;
  }
  // The product's vertices that receive passes (0 without self-shadowing), and their
  // transfers ([v * clusters + k]; empty with light shares, which are all that is kept of
  // them: nothing measures occlusion under linear accumulation).
  size_t productVertices() const { return productVertices_; }
  std::span<const glm::dvec3> productTransfers() const { return productTransfers_; }
  // The product's vertices whose S the last compute() worked out: productVertices(), or 0
  // when it kept the last S (the product's light and the clusters' sources unchanged).
  size_t productVerticesComputed() const { return productComputed_; }
  VertexS s() const {
    return {slots_.receiverVertexOf(), slots_.slots(), receiverS_, productS_, clusters_};
  }
  // Receiver vertices' world positions by slot, then the product's vertices.
  std::span<const core::Vec3> probes() const { return probes_; }
  // Receiver and product vertices whose S used a measured share this frame.
  uint32_t gradedVertices() const { return gradedVertices_; }
  // Threads for the per-vertex work (the renderer's, raster::Renderer::pool()); null: the
  // calling thread only. The bytes are the same either way.
  void setPool(core::JobPool* pool);
  // Wall time of the last compute(): the receiver vertices' part, the product's part.
  int64_t nsReceivers() const { return nsReceivers_; }
  int64_t nsProduct() const { return nsProduct_; }

 private:
  // Vertices per job: a chunk of product vertices' rows is a few kB of transfers.
  static constexpr size_t kVertexChunk = 64;
  template <class VertexOf>
  void intensityRows(size_t vertices, VertexOf vertexOf, std::span<const glm::dvec3> transfers,
                     std::span<core::Rgb16> s, const OcclusionFeedback& feedback);
  void computeReceivers(const ClusterSelection& selection, uint32_t frame,
                        OcclusionFeedback& feedback);
  void computeProduct(const ClusterSelection& selection, const ProductLight& product,
                      OcclusionFeedback& feedback);
  // Whether `selection`'s clusters have the same sources in the same order as at the last
  // call; records them for the next.
  bool sameClusterSources(const ClusterSelection& selection);

  const SceneBundle& bundle_;
  const scene::PatchMesh& mesh_;
  ClusterTransferOptions options_;
  const LightShareKernels& kernels_;  // the best SIMD target's: all give the same bits
  ReceiverVertexSlots slots_;
  size_t clusters_ = 0, productVertices_ = 0;
  uint32_t gradedVertices_ = 0;
  int64_t nsReceivers_ = 0, nsProduct_ = 0;
  core::JobPool* pool_ = nullptr;
  std::vector<std::vector<double>> sharesScratch_{1};  // per worker: a vertex's shares
  // Per worker: a cluster's source rows from the chunk's first vertex, their sums and the
  // shares of those sums (computeProduct).
  struct ProductScratch {
    std::vector<const double*> rows;
    std::vector<double> sum;
    std::vector<uint16_t> shares;
  };
  std::vector<ProductScratch> productScratch_{1};
  std::vector<std::vector<core::Rgb8>> wholeScratch_{1};  // per worker: whole-level S
  std::vector<uint32_t> gradedByWorker_{0};
  std::vector<uint8_t> sets_;                  // per cluster: Fig. 4's set
  std::vector<glm::dvec3> receiverTransfers_;  // [slot * clusters + k]
  std::vector<core::Rgb16> receiverS_;         // [slot * clusters + k]
  std::vector<glm::dvec3> productTransfers_;   // [v * clusters + k]
  std::vector<core::Rgb16> productS_;          // [v * clusters + k]
  uint64_t productGeneration_ = 0;             // of the product light productS_ is from
  size_t productComputed_ = 0;                 // productVerticesComputed()
  std::vector<uint32_t> lastSourceCounts_;     // per cluster, at the last call
  std::vector<uint32_t> lastSources_;          // the clusters' sources back to back
  std::vector<core::Vec3> probes_;
};

}  // namespace penumbra::shadow
