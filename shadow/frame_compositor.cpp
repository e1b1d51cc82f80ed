#include "shadow/frame_compositor.h"

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "scene/portable_trig.h"
#include "shadow/intensity_transfer.h"
#include "shadow/light_frustum.h"

namespace penumbra::shadow {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// Weight of a transfer when shares of light are measured (Rec. 709 luminance).
double luminance(const glm::dvec3& t) {
  return 0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z;
}

}  // namespace

FrameCompositor::FrameCompositor(const SceneBundle& bundle, const CompositorOptions& options)
    : bundle_(bundle),
      options_(options),
      mesh_(patchMeshOf(bundle)),
      hierarchy_(mesh_, bundle.sets, bundle.transfers, options.shafts),
      toneLut_(bundle.tone),
      toneInverse_(bundle.tone) {
  if (bundle.products.empty()) throw std::invalid_argument("scene bundle has no products");
  receiverVertexOf_.assign(mesh_.positions.size(), kNoIndex);
  const RadianceTransfers& t = bundle.transfers;
  for (size_t i = 0; i < t.receiverVertices.size(); ++i) {
    receiverVertexOf_[t.receiverVertices[i]] = static_cast<uint32_t>(i);
  }
  vertexSlot_.assign(t.receiverVertices.size(), 0);
  occlusion_.assign(t.receiverVertices.size(), -1.0f);
  sourceOccluded_.assign(t.receiverVertices.size() * bundle.sets.sources.size(), -1);
  for (uint32_t p = 0; p < mesh_.patches.size(); ++p) {
    if (mesh_.patches[p].emits()) emitters_.push_back(p);
  }
  sourceOfPatch_.assign(mesh_.patches.size(), kNoIndex);
  for (size_t j = 0; j < bundle.sets.sources.size(); ++j) {
    sourceOfPatch_[bundle.sets.sources[j]] = static_cast<uint32_t>(j);
  }
  vertexSlotFrame_.assign(t.receiverVertices.size(), kNoIndex);
  for (const ProductModel& m : bundle.products) lobes_.emplace_back(m.specularExponent);
  if (!bundle.patchRadiance.empty()) {
    environmentRoom_ = roomForEnvironment(bundle.view.staticMesh, bundle.trianglePatch,
                                          bundle.patchRadiance, bundle.tone);
  }
  // The camera centre: the point the view-projection sends to clip (0, 0, *, 0), i.e. the
  // homogeneous point inverse(VP) (0, 0, 1, 0).
  glm::dmat4 vp;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) vp[c][r] = bundle.view.cameraViewProj.m[size_t(4 * r + c)];
  }
  const glm::dvec4 e = glm::inverse(vp) * glm::dvec4(0, 0, 1, 0);
  if (e.w != 0) eye_ = glm::vec3(glm::dvec3(e) / e.w);
}

void FrameCompositor::productModelChanged(uint32_t product) {
  if (product == placedPose_.product) placedPose_.product = ~0u;  // compose() re-places it
}

// The product in world space: turned by yaw about +y, then moved to (x, floor, z).
void FrameCompositor::placeProduct(const ProductPose& pose) {
  if (pose.product >= bundle_.products.size()) {
    throw std::invalid_argument("product " + std::to_string(pose.product) + " does not exist (" +
                                std::to_string(bundle_.products.size()) + " products)");
  }
  if (!std::isfinite(pose.x) || !std::isfinite(pose.z) || !std::isfinite(pose.yawDegrees) ||
      !std::isfinite(pose.lift)) {
    throw std::invalid_argument("product pose is not finite");
  }
  const ProductModel& model = bundle_.products[pose.product];
  if (pose.product != placedPose_.product) {
    productOcclusion_.assign(model.mesh.positions.size(), -1.0f);
    productSourceOccluded_.assign(model.mesh.positions.size() * bundle_.sets.sources.size(), -1);
  }
  placeMesh(model.mesh, pose, placedMesh_);
  placeMesh(model.proxy, pose, placedProxy_);
  productBounds_ = scene::Aabb::emptyBox();
  for (const core::Vec3& p : placedMesh_.positions) productBounds_.extend({p.x, p.y, p.z});
  placedPose_ = pose;
  shadeProduct();
}

// The product's radiance per vertex, through T(). With an irradiance volume in the bundle
// (Gibson & Chalmers 2003 §5): reflectance x E(n)/pi from the volume's SH9 lookup, i.e. the
// light of the whole room with visibility. Without one: a flat diffuse material lit by every
// emitting patch, unshadowed, reflectance x sum_j L_j F(x, n -> j). Either way each source's
// form-factor transfer is kept as that source's L_ij for self-shadowing (§7.2).
void FrameCompositor::shadeProduct() {
  const core::Mesh& m = placedMesh_;
  std::vector<glm::dvec3> normals(m.positions.size(), glm::dvec3(0.0));
  for (size_t t = 0; t < m.triangleCount(); ++t) {
    const core::Vec3 &a = m.positions[m.indices[3 * t]], &b = m.positions[m.indices[3 * t + 1]],
                     &c = m.positions[m.indices[3 * t + 2]];
    const glm::dvec3 n = glm::cross(glm::dvec3(b.x - a.x, b.y - a.y, b.z - a.z),
                                    glm::dvec3(c.x - a.x, c.y - a.y, c.z - a.z));
    for (int k = 0; k < 3; ++k) normals[m.indices[3 * t + size_t(k)]] += n;  // area-weighted
  }
  const glm::dvec3 reflectance(bundle_.products[placedPose_.product].reflectance);
  const size_t vertices = m.positions.size();
  productColours_.resize(vertices);
  productRadiance_.resize(vertices);
  productTransfer_.assign(bundle_.sets.sources.size() * vertices, glm::dvec3(0.0));
  for (size_t v = 0; v < vertices; ++v) {
    const double length = glm::length(normals[v]);
    const glm::dvec3 n = length > 0 ? normals[v] / length : glm::dvec3(0, 1, 0);
    const glm::dvec3 x(m.positions[v].x, m.positions[v].y, m.positions[v].z);
    // Each emitter's transfer once: it adds to the vertex's radiance, and a source's is kept
    // as that source's L_ij for self-shadowing.
    glm::dvec3 radiance(0.0);
    for (uint32_t p : emitters_) {
      const scene::Patch& patch = mesh_.patches[p];
      const glm::dvec3 transfer =
          reflectance * patch.emission *
          scene::pointToPatchFormFactor(x, n, patch.centre, patch.normal, patch.area);
      radiance += transfer;
      if (sourceOfPatch_[p] != kNoIndex)
        productTransfer_[sourceOfPatch_[p] * vertices + v] = transfer;
    }
    productRadiance_[v] = radiance;
    productColours_[v] = bundle_.tone.map(radiance);
  }
  if (bundle_.irradiance.empty() || !options_.shadeFromVolume) return;
  const std::vector<glm::vec3> vertexN = vertexNormals(m);
  volumeRadiance_.resize(vertices);
  shadeVerticesDiffuse(bundle_.irradiance, m.positions, vertexN, glm::vec3(reflectance), toneLut_,
                       productColours_, volumeRadiance_);
  for (size_t v = 0; v < vertices; ++v) productRadiance_[v] = glm::dvec3(volumeRadiance_[v]);

  // §5 specular: the room reflected in a Phong lobe, from a cube map rendered at the
  // product's centre (Fig. 9), added in radiance before T().
  const ProductModel& model = bundle_.products[placedPose_.product];
  if (!options_.specular || environmentRoom_.mesh.positions.empty() ||
      !(model.specular.x > 0 || model.specular.y > 0 || model.specular.z > 0)) {
    return;
  }
  const float farDistance =
      2.0f * static_cast<float>(glm::length(hierarchy_.receiverNodes()[0].bounds.size())) + 1.0f;
  renderEnvironmentMap(environmentRoom_, glm::vec3(productBounds_.centre()),
                       options_.environmentMapSize, farDistance, environment_);
  const PhongLobe& lobe = lobes_[placedPose_.product];
  for (size_t v = 0; v < vertices; ++v) {
    const glm::vec3 p(m.positions[v].x, m.positions[v].y, m.positions[v].z);
    const glm::vec3 s = specularRadiance(environment_, toneInverse_, lobe, p, vertexN[v], eye_);
    const glm::vec3 l(volumeRadiance_[v].x + model.specular.x * s.x,
                      volumeRadiance_[v].y + model.specular.y * s.y,
                      volumeRadiance_[v].z + model.specular.z * s.z);
    productRadiance_[v] = glm::dvec3(l);
    productColours_[v] = toneLut_.map(l);
  }
}

void FrameCompositor::compose(const ProductPose& pose, size_t passes, uint32_t frame,
                              raster::FrameContent& out, CompositeStats& stats) {
  stats = CompositeStats{};
  auto t0 = Clock::now();
  if (pose.product != placedPose_.product || pose.x != placedPose_.x || pose.z != placedPose_.z ||
      pose.yawDegrees != placedPose_.yawDegrees || pose.lift != placedPose_.lift) {
    placeProduct(pose);
  }
  stats.msObject = msSince(t0);

  // §6.1: sources the product may block, and the receivers that may see it happen.
  t0 = Clock::now();
  hierarchy_.traverse(productBounds_, frame, traversal_);
  stats.msTraversal = msSince(t0);
  stats.occludedSources = static_cast<uint32_t>(traversal_.sources.size());
  stats.receiverPatches = static_cast<uint32_t>(traversal_.receivers.size());
  stats.shaftsVisited = static_cast<uint32_t>(traversal_.shaftsVisited);

  // §8: at most `passes` clusters covering every blocked source exactly once.
  t0 = Clock::now();
  selectSourceClusters(hierarchy_, traversal_.sources, frame, passes, selection_);
  const size_t clusters = selection_.clusters.size();
  stats.clusters = static_cast<uint32_t>(clusters);
  stats.msClusters = msSince(t0);

  // The frame's receiver vertices, each given a slot.
  t0 = Clock::now();
  frameVertices_.clear();
  for (uint32_t patch : traversal_.receivers) {
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
  stats.receiverVertices = static_cast<uint32_t>(frameVertices_.size());

  // Each cluster's transfer to each slot: the sum of its blocked sources' L_ij (§8: the
  // cluster stands for exactly those sources, so all blocked energy is accounted for).
  const RadianceTransfers& tr = bundle_.transfers;
  const size_t sources = bundle_.sets.sources.size();
  clusterTransfer_.assign(frameVertices_.size() * clusters, glm::dvec3(0.0));
  clusterSeen_.assign(frameVertices_.size() * clusters, 0.0);
  clusterOccluded_.assign(frameVertices_.size() * clusters, 0.0);
  for (size_t k = 0; k < clusters; ++k) {
    const SourceCluster& cl = selection_.clusters[k];
    for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
      const uint32_t s = selection_.sources[i];
      for (uint32_t e = tr.sourceStart[s]; e < tr.sourceStart[s + 1]; ++e) {
        const uint32_t rv = tr.entryVertex[e];
        if (vertexSlotFrame_[rv] != frame) continue;
        const size_t at = vertexSlot_[rv] * clusters + k;
        clusterTransfer_[at] += glm::dvec3(tr.entryTransfer[e]);
        seenShare(sourceOccluded_[rv * sources + s], glm::dvec3(tr.entryTransfer[e]), at);
      }
    }
  }
  // §7.1.1, Fig. 4 per receiver vertex, clusters in decreasing transfer (selection order),
  // each in the set of its representative patch's stable id.
  setsScratch_.resize(clusters);
  for (size_t k = 0; k < clusters; ++k) {
    const uint32_t patch = bundle_.sets.sources[selection_.clusters[k].representative];
    setsScratch_[k] = static_cast<uint8_t>(sourceSet(options_.setSeed, patch));
  }
  clusterS_.resize(frameVertices_.size() * clusters);
  probes_.resize(frameVertices_.size());
  for (size_t slot = 0; slot < frameVertices_.size(); ++slot) {
    const uint32_t rv = frameVertices_[slot];
    probes_[slot] = bundle_.view.staticMesh.positions[tr.receiverVertices[rv]];
    const glm::dvec3 total(tr.vertexRadiance[rv]);
    const std::span<const glm::dvec3> transfers(clusterTransfer_.data() + slot * clusters,
                                                clusters);
    const std::span<core::Rgb8> s(clusterS_.data() + slot * clusters, clusters);
    if (options_.gradedTransfers && occlusion_[rv] >= 0.0f) {
      intensityTransfersForOcclusions(total, transfers,
                                      clusterShares(slot * clusters, clusters, occlusion_[rv]),
                                      bundle_.tone, s);
      ++stats.gradedVertices;
    } else {
      intensityTransfers(total, transfers, setsScratch_, bundle_.tone, s);
    }
  }
  // The same for the product's own vertices (self-shadowing, §7.2).
  const size_t productVertices = options_.selfShadowing ? placedMesh_.positions.size() : 0;
  productCluster_.assign(productVertices * clusters, glm::dvec3(0.0));
  productS_.resize(productVertices * clusters);
  clusterSeen_.assign(productVertices * clusters, 0.0);
  clusterOccluded_.assign(productVertices * clusters, 0.0);
  for (size_t k = 0; k < clusters; ++k) {
    const SourceCluster& cl = selection_.clusters[k];
    for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
      const uint32_t source = selection_.sources[i];
      const glm::dvec3* row = &productTransfer_[size_t(source) * productVertices];
      for (size_t v = 0; v < productVertices; ++v) {
        productCluster_[v * clusters + k] += row[v];
        seenShare(productSourceOccluded_[v * sources + source], row[v], v * clusters + k);
      }
    }
  }
  for (size_t v = 0; v < productVertices; ++v) {
    const std::span<const glm::dvec3> transfers(productCluster_.data() + v * clusters, clusters);
    const std::span<core::Rgb8> s(productS_.data() + v * clusters, clusters);
    if (options_.gradedTransfers && productOcclusion_[v] >= 0.0f) {
      intensityTransfersForOcclusions(productRadiance_[v], transfers,
                                      clusterShares(v * clusters, clusters, productOcclusion_[v]),
                                      bundle_.tone, s);
      ++stats.gradedVertices;
    } else {
      intensityTransfers(productRadiance_[v], transfers, setsScratch_, bundle_.tone, s);
    }
  }
  // Probes: the receiver vertices, then the product's own vertices.
  probes_.resize(frameVertices_.size() + productVertices);
  std::copy(placedMesh_.positions.begin(),
            placedMesh_.positions.begin() + std::ptrdiff_t(productVertices),
            probes_.begin() + std::ptrdiff_t(frameVertices_.size()));
  stats.msTransfers = msSince(t0);

  // The frame description (Fig. 2): background, product, proxy, one pass per cluster.
  out.background = bundle_.background;
  out.objects.resize(1);
  out.objects[0].mesh = placedMesh_;
  out.objects[0].colours = productColours_;
  out.occluders.resize(1);
  out.occluders[0] = placedProxy_;
  out.accumulation = options_.accumulation;
  out.passes.resize(clusters);
  passCluster_.clear();
  size_t used = 0;
  const double farDistance = 2.0 * glm::length(hierarchy_.receiverNodes()[0].bounds.size()) + 1.0;
  for (size_t k = 0; k < clusters; ++k) {
    const uint32_t patch = bundle_.sets.sources[selection_.clusters[k].representative];
    const auto frustum =
        fitLightFrustum(glm::dvec3(bundle_.patches[patch].centre), productBounds_, farDistance);
    if (!frustum) {
      // The light sits inside the product's bounding sphere (e.g. a product larger than the
      // room): no shadow map can hold the product, so this cluster casts no shadow.
      ++stats.skippedClusters;
      continue;
    }
    passCluster_.push_back(static_cast<uint32_t>(k));
    raster::ShadowPass& pass = out.passes[used];
    pass.lightViewProj = frustum->rasterViewProj;
    pass.shadowMapSize = options_.shadowMapSize;
    pass.depthBias = options_.depthBias;
    pass.pcf2x2 = options_.pcf2x2;
    pass.occluder = 0;
    pass.receiverTriangles.clear();
    pass.receiverS.clear();
    // A receiver wholly outside one side of the light's frustum can get no shadow from this
    // pass: its pixels fall outside the map (M = 0, spec §7). Tested against a frustum 5%
    // wider, so float rounding in the pixel path cannot disagree; the product stays inside
    // the map's inscribed circle, so the map's edge texels hold no occluder anyway.
    const glm::dmat4 cull =
        glm::scale(glm::dmat4(1.0), glm::dvec3(1.0 / 1.05, 1.0 / 1.05, 1.0)) * frustum->viewProj;
    for (uint32_t p : traversal_.receivers) {
      const uint32_t first = mesh_.patches[p].firstTriangle;
      for (uint32_t t = first; t < first + 2; ++t) {
        const uint32_t* v = &mesh_.indices[3 * size_t(t)];
        if (options_.cullReceivers &&
            !triangleMayReceive(cull, mesh_.positions[v[0]], mesh_.positions[v[1]],
                                mesh_.positions[v[2]])) {
          continue;
        }
        std::array<core::Rgb8, 3> s{};
        bool any = false;
        for (int c = 0; c < 3; ++c) {
          const uint32_t rv = receiverVertexOf_[mesh_.indices[3 * size_t(t) + size_t(c)]];
          if (rv == kNoIndex) continue;
          s[size_t(c)] = clusterS_[vertexSlot_[rv] * clusters + k];
          any = any || s[size_t(c)].r != 0 || s[size_t(c)].g != 0 || s[size_t(c)].b != 0;
        }
        if (!any) continue;  // nothing to subtract on this triangle for this cluster
        pass.receiverTriangles.push_back(t);
        pass.receiverS.insert(pass.receiverS.end(), s.begin(), s.end());
      }
    }
    pass.objectTriangles.clear();
    pass.objectS.clear();
    pass.objectDepthBias = options_.objectDepthBias;
    for (size_t t = 0; productVertices > 0 && t < placedMesh_.triangleCount(); ++t) {
      std::array<core::Rgb8, 3> s{};
      bool any = false;
      for (int c = 0; c < 3; ++c) {
        s[size_t(c)] = productS_[size_t(placedMesh_.indices[3 * t + size_t(c)]) * clusters + k];
        any = any || s[size_t(c)].r != 0 || s[size_t(c)].g != 0 || s[size_t(c)].b != 0;
      }
      if (!any) continue;
      pass.objectTriangles.push_back(static_cast<uint32_t>(t));
      pass.objectS.insert(pass.objectS.end(), s.begin(), s.end());
    }
    ++used;
  }
  out.passes.resize(used);
  stats.passes = static_cast<uint32_t>(used);
}

void FrameCompositor::setShadowMapSize(uint32_t size) {
  if (size < 16 || size > raster::kMaxShadowMapSize || size % 16 != 0) {
    throw std::invalid_argument("shadow map size " + std::to_string(size) +
                                " is not a multiple of 16 in 16..4096");
  }
  options_.shadowMapSize = size;
}

void FrameCompositor::observe(std::span<const uint8_t> masks) {
  const size_t passes = passCluster_.size();
  if (masks.size() != probes_.size() * passes) {
    throw std::invalid_argument("observe: masks do not match the last composed frame");
  }
  const size_t clusters = selection_.clusters.size();
  const size_t sources = bundle_.sets.sources.size();
  // The transfer-weighted share of a probe's blocked light that was really occluded, summed
  // in pass order; -1 when nothing reaches it. `transfers` are the probe's per-cluster ones.
  // Also which sources each pass's mask occluded at the probe, into `seen` (its row of
  // sourceOccluded_ or productSourceOccluded_); sources without a pass are not seen.
  auto observeProbe = [&](size_t probe, const glm::dvec3* transfers, int8_t* seen) {
    std::fill(seen, seen + sources, int8_t{-1});
    double blocked = 0, total = 0;
    for (size_t k = 0; k < passes; ++k) {
      const glm::dvec3& t = transfers[passCluster_[k]];
      const double weight = luminance(t);
      const bool occluded = masks[probe * passes + k] != 0;
      total += weight;
      blocked += occluded ? weight : 0.0;
      const SourceCluster& cl = selection_.clusters[passCluster_[k]];
      for (uint32_t i = cl.firstSource; i < cl.firstSource + cl.sourceCount; ++i) {
        seen[selection_.sources[i]] = occluded ? 1 : 0;
      }
    }
    return total > 0 ? static_cast<float>(blocked / total) : -1.0f;
  };
  for (size_t slot = 0; slot < frameVertices_.size(); ++slot) {
    const uint32_t rv = frameVertices_[slot];
    occlusion_[rv] = observeProbe(slot, clusterTransfer_.data() + slot * clusters,
                                  sourceOccluded_.data() + size_t(rv) * sources);
  }
  for (size_t v = 0; v + frameVertices_.size() < probes_.size(); ++v) {
    productOcclusion_[v] =
        observeProbe(frameVertices_.size() + v, productCluster_.data() + v * clusters,
                     productSourceOccluded_.data() + v * sources);
  }
}

// Adds one source's transfer to cluster entry `at`'s seen (and occluded) luminance when the
// last observation saw that source at this vertex (`state` 0 or 1).
void FrameCompositor::seenShare(int8_t state, const glm::dvec3& transfer, size_t at) {
  if (state < 0) return;
  const double weight = luminance(transfer);
  clusterSeen_[at] += weight;
  if (state > 0) clusterOccluded_[at] += weight;
}

// The expected occluded share of each of `clusters` clusters from entry `first` on: the
// seen sources' occluded share, or `fallback` (the vertex's one measured share) for a
// cluster none of whose sources was seen, or for all with perClusterShares off.
std::span<const double> FrameCompositor::clusterShares(size_t first, size_t clusters,
                                                       float fallback) {
  sharesScratch_.assign(clusters, double(fallback));
  if (!options_.perClusterShares) return sharesScratch_;
  for (size_t k = 0; k < clusters; ++k) {
    const double seen = clusterSeen_[first + k];
    if (seen > 0) sharesScratch_[k] = std::min(1.0, clusterOccluded_[first + k] / seen);
  }
  return sharesScratch_;
}

}  // namespace penumbra::shadow
