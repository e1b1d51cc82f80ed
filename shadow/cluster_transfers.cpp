#include "shadow/cluster_transfers.h"

#include <algorithm>

#include "core/clock.h"

#include "shadow/intensity_transfer.h"
#include "shadow/light_share_kernels.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {

ClusterTransfers::ClusterTransfers(const SceneBundle& bundle, const scene::PatchMesh& mesh,
                                   const ClusterTransferOptions& options)
    : bundle_(bundle),
      mesh_(mesh),
      options_(options),
      kernels_(lightShareKernelsFor(simd::bestIsa())),
      slots_(bundle.transfers, mesh) {}

void ClusterTransfers::compute(std::span<const uint32_t> receiverPatches,
                               const ClusterSelection& selection, uint32_t frame,
                               const ProductLight& product, OcclusionFeedback& feedback) {
  clusters_ = selection.clusters.size();
  gradedVertices_ = 0;
  core::Stopwatch watch;
  slots_.gather(mesh_, receiverPatches, frame);
  computeReceivers(selection, frame, feedback);
  nsReceivers_ = watch.lapNs();
  computeProduct(selection, product, feedback);
  nsProduct_ = watch.lapNs();
}

void ClusterTransfers::setPool(core::JobPool* pool) {
  pool_ = pool;
  const size_t threads = pool ? size_t(pool->threads()) : 1;
  sharesScratch_.resize(threads);
  productScratch_.resize(threads);
  wholeScratch_.resize(threads);
  gradedByWorker_.assign(threads, 0);
}

// Fig. 4, or the graded transfers at the measured shares, for `vertices` vertices from
// `first` on: total radiance, transfers and S rows by vertex (intensity_transfer.h), the
// feedback's share per vertex. Rows are independent: chunks of them run on the pool.
template <class VertexOf>
void ClusterTransfers::intensityRows(size_t vertices, VertexOf vertexOf,
                                     std::span<const glm::dvec3> transfers,
                                     std::span<core::Rgb16> s, const OcclusionFeedback& feedback) {
  const size_t clusters = clusters_;
  std::fill(gradedByWorker_.begin(), gradedByWorker_.end(), 0u);
  core::forEachChunk(pool_, vertices, kVertexChunk, [&](size_t begin, size_t end, int worker) {
    std::vector<double>& shares = sharesScratch_[size_t(worker)];
    std::vector<core::Rgb8>& whole = wholeScratch_[size_t(worker)];
    shares.resize(clusters);
    whole.resize(options_.kind == TransferKind::kWholeLevels ? clusters : 0);
    for (size_t slot = begin; slot < end; ++slot) {
      // Named copies, not a structured binding: the lambda below captures them (clang < 16
      // refuses to capture bindings).
      const auto vertex = vertexOf(slot);
      const glm::dvec3 total = vertex.first;
      const auto share = vertex.second;
      const std::span<const glm::dvec3> row(transfers.data() + slot * clusters, clusters);
      const std::span<core::Rgb16> out(s.data() + slot * clusters, clusters);
      if (options_.kind == TransferKind::kLightShares) {
        lightShares(total, row, out);
        continue;
      }
      const bool graded = options_.gradedTransfers && share >= 0.0f;
      if (graded) feedback.clusterShares(slot * clusters, share, shares);
      const auto transfersInto = [&](auto into) {
        if (graded) {
          intensityTransfersForOcclusions(total, row, std::span<const double>(shares), bundle_.tone,
                                          into);
        } else {
          intensityTransfers(total, row, std::span<const uint8_t>(sets_), bundle_.tone, into);
        }
      };
      if (options_.kind == TransferKind::kFineLevels) {
        transfersInto(out);
      } else {
        transfersInto(std::span<core::Rgb8>(whole));
        std::transform(whole.begin(), whole.end(), out.begin(), core::Rgb16::fromLevels);
      }
      if (graded) ++gradedByWorker_[size_t(worker)];
    }
  });
  for (uint32_t n : gradedByWorker_) gradedVertices_ += n;
}

void ClusterTransfers::computeReceivers(const ClusterSelection& selection, uint32_t frame,
                                        OcclusionFeedback& feedback) {
  // Each cluster's transfer to each slot: the sum of its blocked sources' L_ij (§8: the
  // cluster stands for exactly those sources, so all blocked energy is accounted for).
  const RadianceTransfers& tr = bundle_.transfers;
  const size_t clusters = clusters_;
  const std::span<const uint32_t> frameVertices = slots_.frameVertices();
  receiverTransfers_.assign(frameVertices.size() * clusters, glm::dvec3(0.0));
  feedback.beginShares(frameVertices.size() * clusters);
  for (size_t k = 0; k < clusters; ++k) {
    const SourceCluster& cl = selection.clusters[k];
    for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
      const uint32_t s = selection.sources[i];
      for (uint32_t e = tr.sourceStart[s]; e < tr.sourceStart[s + 1]; ++e) {
        const uint32_t rv = tr.entryVertex[e];
        if (!slots_.inFrame(rv, frame)) continue;
        const size_t at = slots_.slot(rv) * clusters + k;
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
  receiverS_.resize(frameVertices.size() * clusters);
  probes_.resize(frameVertices.size());
  for (size_t slot = 0; slot < frameVertices.size(); ++slot) {
    probes_[slot] = bundle_.view.staticMesh.positions[tr.receiverVertices[frameVertices[slot]]];
  }
  intensityRows(
      frameVertices.size(),
      [&](size_t slot) {
        const uint32_t rv = frameVertices[slot];
        return std::pair{glm::dvec3(tr.vertexRadiance[rv]), feedback.receiverShare(rv)};
      },
      receiverTransfers_, receiverS_, feedback);
}

// The same for the product's own vertices (self-shadowing, §7.2).
void ClusterTransfers::computeProduct(const ClusterSelection& selection,
                                      const ProductLight& product, OcclusionFeedback& feedback) {
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(double), "dvec3 rows are read as doubles");
  const size_t clusters = clusters_;
  const size_t frameVertices = slots_.frameVertices().size();
  productVertices_ = options_.selfShadowing ? product.positions.size() : 0;
  // Only the graded transfers read the seen shares (clusterShares), and only S of the
  // transfers; light shares need neither, so with them the transfers are not kept (at 50
  // clusters the bunny's take 2.2 MB, written a vertex's row apart). Every entry kept is
  // written below: no clearing.
  const bool lightShares = options_.kind == TransferKind::kLightShares;
  productTransfers_.resize(lightShares ? 0 : productVertices_ * clusters);
  productS_.resize(productVertices_ * clusters);
  // Light shares are a function of the product's light and the clusters' sources alone: a
  // product that did not move under the same clusters keeps its S (the kiosk's product
  // stands still most of the time).
  const bool sameSources = sameClusterSources(selection);
  const bool unchanged = lightShares && sameSources && product.generation != 0 &&
                         product.generation == productGeneration_;
  productGeneration_ = product.generation;
  // Probes: the receiver vertices, then the product's own vertices.
  probes_.resize(frameVertices + productVertices_);
  std::copy(product.positions.begin(), product.positions.begin() + std::ptrdiff_t(productVertices_),
            probes_.begin() + std::ptrdiff_t(frameVertices));
  productComputed_ = unchanged ? 0 : productVertices_;
  if (unchanged) return;
  const bool seenShares = !lightShares && options_.gradedTransfers;
  if (seenShares) feedback.beginShares(productVertices_ * clusters);
  // Per chunk and cluster, the chunk's sums as one run of doubles (x, y, z by vertex): the
  // cluster's source rows are added element by element (light_share_kernels.h), so entry
  // (v, k) still sums its cluster's sources in selection order from 0 whichever chunk holds
  // v (the serial sums bit for bit), in vector lanes over contiguous doubles. With light
  // shares, S is taken from the run at once (the product's rows are not read back).
  core::forEachChunk(
      pool_, productVertices_, kVertexChunk, [&](size_t begin, size_t end, int worker) {
        ProductScratch& scratch = productScratch_[size_t(worker)];
        const size_t n = 3 * (end - begin);
        scratch.sum.resize(n);
        scratch.shares.resize(lightShares ? n : 0);
        const double* whole = &product.radiance[begin].x;
        for (size_t k = 0; k < clusters; ++k) {
          const SourceCluster& cl = selection.clusters[k];
          scratch.rows.clear();
          for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
            const uint32_t source = selection.sources[i];
            const glm::dvec3* row =
                product.sourceTransfers.data() + size_t(source) * productVertices_;
            scratch.rows.push_back(&row[begin].x);
            if (!seenShares) continue;
            for (size_t v = begin; v < end; ++v) {
              feedback.addProductSource(v, source, row[v], v * clusters + k);
            }
          }
          kernels_.sumRows(scratch.rows.data(), scratch.rows.size(), n, scratch.sum.data());
          const double* sum = scratch.sum.data();
          if (lightShares) {
            kernels_.shares(sum, whole, n, scratch.shares.data());
            const uint16_t* share = scratch.shares.data();
            for (size_t v = begin, j = 0; v < end; ++v, j += 3) {
              productS_[v * clusters + k] = {share[j], share[j + 1], share[j + 2]};
            }
          } else {
            for (size_t v = begin, j = 0; v < end; ++v, j += 3) {
              productTransfers_[v * clusters + k] = glm::dvec3(sum[j], sum[j + 1], sum[j + 2]);
            }
          }
        }
      });
  if (!lightShares) {
    intensityRows(
        productVertices_,
        [&](size_t v) {
          return std::pair{product.radiance[v], feedback.productShare(v)};
        },
        productTransfers_, productS_, feedback);
  }
}

bool ClusterTransfers::sameClusterSources(const ClusterSelection& selection) {
  bool same = selection.clusters.size() == lastSourceCounts_.size();
  size_t at = 0;
  for (size_t k = 0; same && k < selection.clusters.size(); ++k) {
    const SourceCluster& cl = selection.clusters[k];
    same = cl.sourceCount == lastSourceCounts_[k] &&
           std::equal(selection.sources.begin() + cl.firstSource,
                      selection.sources.begin() + cl.firstSource + cl.sourceCount,
                      lastSources_.begin() + std::ptrdiff_t(at));
    at += cl.sourceCount;
  }
  if (same) return true;
  lastSourceCounts_.clear();
  lastSources_.clear();
  for (const SourceCluster& cl : selection.clusters) {
    lastSourceCounts_.push_back(cl.sourceCount);
    lastSources_.insert(lastSources_.end(), selection.sources.begin() + cl.firstSource,
                        selection.sources.begin() + cl.firstSource + cl.sourceCount);
  }
  return false;
}

}  // namespace penumbra::shadow
