#include "shadow/pass_list.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <stdexcept>

#include "shadow/area_penumbra.h"
#include "shadow/cluster_map_size.h"
#include "shadow/light_frustum.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {
namespace {

bool anyS(const std::array<core::Rgb16, 3>& s) {
  bool any = false;
  for (const core::Rgb16& c : s) any = any || c.r != 0 || c.g != 0 || c.b != 0;
  return any;
}

}  // namespace

PassList::PassList(const SceneBundle& bundle, const scene::PatchMesh& mesh, const scene::Aabb& room)
    : bundle_(bundle),
      mesh_(mesh),
      room_(room),
      farDistance_(2.0 * glm::length(room.size()) + 1.0) {}

glm::dvec3 PassList::clusterCentroid(const SourceCluster& cluster,
                                     std::span<const uint32_t> sources) const {
  const auto centre = [&](uint32_t source) {
    return glm::dvec3(bundle_.patches[bundle_.sets.sources[source]].centre);
  };
  // One source: its own patch centre, bit for bit (a weighted mean of one point need not
  // round back to it), so a pass per source casts from exactly where §8 says.
  if (cluster.sourceCount == 1) return centre(cluster.representative);
  // Why the centroid and not §8's most energetic patch: a cluster's sources throw shadows
  // whose edges lie spread around the edge cast from their energy-weighted centroid, so
  // one hard edge there splits the misplaced light evenly on both sides; cast from the
  // brightest patch, the whole cluster's edge sits at one end of that spread. Measured on
  // the showroom at 50 passes: chair against the wall 1.256 → 0.993 levels (docs/accuracy.md).
  glm::dvec3 sum(0.0);
  double weight = 0;
  for (uint32_t i = cluster.firstSource; i < cluster.firstSource + cluster.sourceCount; ++i) {
    const double w = bundle_.transfers.sourceAverage[sources[i]];
    sum += w * centre(sources[i]);
    weight += w;
  }
  return weight > 0 ? sum / weight : centre(cluster.representative);
}

uint32_t fineProxyPassesFor(uint32_t fineProxyPasses, size_t clusters) {
  if (clusters <= kFineProxyReferencePasses) return fineProxyPasses;
  // ceil(clusters * fineProxyPasses / 50) in integers; both factors are below 2^32.
  const uint64_t scaled = (uint64_t{clusters} * fineProxyPasses + kFineProxyReferencePasses - 1) /
                          kFineProxyReferencePasses;
  return static_cast<uint32_t>(std::min<uint64_t>(scaled, clusters));
}

uint32_t PassList::build(const PassListOptions& options, const ClusterSelection& selection,
                         std::span<const uint32_t> receiverPatches, const core::Mesh& product,
                         const scene::Aabb& productBounds, const VertexS& s,
                         std::vector<raster::ShadowPass>& passes) {
  const size_t clusters = selection.clusters.size();
  const uint32_t finePasses = fineProxyPassesFor(options.fineProxyPasses, clusters);
  beginBuild(clusters, passes);
  uint32_t skipped = 0;
  // The frusta in cluster order (which clusters get a pass), then each pass's triangles.
  for (size_t k = 0; k < clusters; ++k) {
    const SourceCluster& cluster = selection.clusters[k];
    const glm::dvec3 representative(
        bundle_.patches[bundle_.sets.sources[cluster.representative]].centre);
    glm::dvec3 light = clusterCentroid(cluster, selection.sources);
    auto frustum = fitLightFrustum(light, productBounds, farDistance_);
    // The centroid of a widely spread cluster can fall inside the product's bounding sphere
    // where the representative patch does not: then the map is cast from that patch (§8).
    if (!frustum) {
      light = representative;
      frustum = fitLightFrustum(light, productBounds, farDistance_);
    }
    if (!frustum) {
      // The light sits inside the product's bounding sphere (e.g. a product larger than the
      // room): no shadow map can hold the product, so this cluster casts no shadow.
      ++skipped;
      continue;
    }
    const uint32_t mapSize =
        options.texelsPerShadowPixel > 0
            ? clusterMapSize(shadowFootprintPx(bundle_.view, *frustum, light, room_),
                             options.texelsPerShadowPixel, options.shadowMapSize)
            : options.shadowMapSize;
    addPass(options, *frustum, k, mapSize, options.depthBias, options.objectDepthBias, finePasses,
            passes);
    if (options.areaPenumbrae && options.pcf2x2 && mapSize <= raster::kMaxAreaPenumbraMapSize) {
      const glm::dvec3 axis = glm::normalize(frustum->sphereCentre - light);
      const double scale = penumbraScale(
          *frustum, clusterHalfWidth(bundle_, cluster, selection.sources, light, axis), mapSize);
      // A light whose box stays within half a texel from the near plane to the far one
      // (window depths 0 and 1) keeps its hard pass: the same bytes in the frustum, and no
      // coverage to sum.
      if (scale > raster::kMinPenumbraHalfWidth) {
        passes[passCluster_.size() - 1].penumbraScale = static_cast<float>(scale);
      }
    }
  }
  fillPasses(
      options, [&](size_t) { return receiverPatches; }, receiverPatches.size(), product, s, passes);
  return skipped;
}

void PassList::buildDirectional(const PassListOptions& options,
                                std::span<const glm::dvec3> towardsLight,
                                std::span<const uint32_t> receiverPatches,
                                std::span<const uint32_t> lightPatchStart,
                                const core::Mesh& product, const scene::Aabb& productBounds,
                                const scene::Aabb& room, const VertexS& s,
                                std::vector<raster::ShadowPass>& passes) {
  if (lightPatchStart.size() != towardsLight.size() + 1) {
    throw std::invalid_argument("PassList::buildDirectional: patch ranges do not match the lights");
  }
  beginBuild(towardsLight.size(), passes);
  size_t widest = 0;
  for (size_t k = 0; k < towardsLight.size(); ++k) {
    const auto frustum = fitDirectionalFrustum(towardsLight[k], productBounds, room);
    if (!frustum) continue;
    // Window depth is linear here: a bias of b metres is b / (zFar - zNear). The same
    // distances as the point lights' biases give at the product (~5 mm and ~2.7 cm at 2 m).
    const double perMetre = 1.0 / (frustum->zFar - frustum->zNear);
    addPass(options, *frustum, k, options.shadowMapSize,
            static_cast<float>(options.directionalBiasMetres * perMetre),
            static_cast<float>(options.directionalObjectBiasMetres * perMetre),
            options.fineProxyPasses, passes);
    widest = std::max<size_t>(widest, lightPatchStart[k + 1] - lightPatchStart[k]);
  }
  fillPasses(
      options,
      [&](size_t k) {
        return receiverPatches.subspan(lightPatchStart[k],
                                       lightPatchStart[k + 1] - lightPatchStart[k]);
      },
      widest, product, s, passes);
}

void PassList::beginBuild(size_t lights, std::vector<raster::ShadowPass>& passes) {
  passes.resize(lights);
  passCluster_.clear();
  passViewProj_.clear();
}

void PassList::addPass(const PassListOptions& options, const LightFrustum& frustum, size_t column,
                       uint32_t mapSize, float depthBias, float objectDepthBias,
                       uint32_t finePasses, std::vector<raster::ShadowPass>& passes) {
  const size_t index = passCluster_.size();
  raster::ShadowPass& pass = passes[index];
  passCluster_.push_back(static_cast<uint32_t>(column));
  pass.lightViewProj = frustum.rasterViewProj;
  pass.shadowMapSize = mapSize;
  pass.depthBias = depthBias;
  pass.pcf2x2 = options.pcf2x2;
  pass.occluder = index < finePasses ? 1 : 0;
  pass.cullBackFaces = options.closedOccluders[pass.occluder];
  pass.objectDepthBias = objectDepthBias;
  pass.penumbraScale = 0;  // build() sets it for area penumbrae
  passViewProj_.push_back(frustum.viewProj);
}

template <class PatchesOf>
void PassList::fillPasses(const PassListOptions& options, PatchesOf patchesOf, size_t mostPatches,
                          const core::Mesh& product, const VertexS& s,
                          std::vector<raster::ShadowPass>& passes) {
  const size_t used = passCluster_.size();
  passes.resize(used);
  // Each pass's lists at their largest size, here on the calling thread: the workers then
  // never allocate. (Grown on whichever worker filled a pass, in glibc's per-thread arenas,
  // they held the soak's heap in use at 55 MB at frame 2000 against 42 MB reserved here.)
  const size_t productTriangles = s.productS.empty() ? 0 : product.triangleCount();
  for (raster::ShadowPass& pass : passes) {
    pass.receiverTriangles.reserve(2 * mostPatches);
    pass.receiverS.reserve(6 * mostPatches);
    pass.objectTriangles.reserve(productTriangles);
    pass.objectS.reserve(3 * productTriangles);
  }
  const size_t workers = pool_ ? size_t(pool_->threads()) : 1;
  outcodes_.resize(workers);
  for (OutcodeScratch& scratch : outcodes_) {
    scratch.codes.resize(mesh_.positions.size(), kUnknownCode);
    scratch.coded.reserve(mesh_.positions.size());
  }
  core::forEachChunk(pool_, used, 1, [&](size_t i, size_t, int worker) {
    addReceivers(options, passViewProj_[i], patchesOf(passCluster_[i]), s, passCluster_[i],
                 passes[i], worker);
  });
  addProduct(product, s, passes);
}

void PassList::addReceivers(const PassListOptions& options, const glm::dmat4& lightViewProj,
                            std::span<const uint32_t> receiverPatches, const VertexS& s, size_t k,
                            raster::ShadowPass& pass, int worker) {
  pass.receiverTriangles.clear();
  pass.receiverS.clear();
  // A receiver wholly outside one side of the light's frustum can get no shadow from this
  // pass: its pixels fall outside the map (M = 0, spec §7). Tested against a frustum 5%
  // wider, so float rounding in the pixel path cannot disagree; the product stays inside
  // the map's inscribed circle, so the map's edge texels hold no occluder anyway.
  const glm::dmat4 cull =
      glm::scale(glm::dmat4(1.0), glm::dvec3(1.0 / 1.05, 1.0 / 1.05, 1.0)) * lightViewProj;
  // triangleMayReceive's test from each vertex's code, computed once per pass: a receiver
  // vertex is a corner of up to 8 triangles (more at a T-junction).
  std::vector<uint8_t>& codes = outcodes_[size_t(worker)].codes;
  std::vector<uint32_t>& coded = outcodes_[size_t(worker)].coded;
  const auto codeOf = [&](uint32_t v) {
    if (codes[v] == kUnknownCode) {
      codes[v] = clipOutcode(cull, mesh_.positions[v]);
      coded.push_back(v);
    }
    return codes[v];
  };
  for (uint32_t p : receiverPatches) {
    const uint32_t first = mesh_.patches[p].firstTriangle;
    for (uint32_t t = first; t < first + 2; ++t) {
      const uint32_t* v = &mesh_.indices[3 * size_t(t)];
      if (options.cullReceivers && (codeOf(v[0]) & codeOf(v[1]) & codeOf(v[2])) != 0) continue;
      std::array<core::Rgb16, 3> corners{};
      for (int c = 0; c < 3; ++c) {
        const uint32_t rv = s.receiverVertexOf[v[c]];
        if (rv == kNoIndex) continue;
        corners[size_t(c)] = s.receiverS[size_t(s.vertexSlot[rv]) * s.clusters + k];
      }
      if (!anyS(corners)) continue;  // nothing to subtract on this triangle for this cluster
      pass.receiverTriangles.push_back(t);
      pass.receiverS.insert(pass.receiverS.end(), corners.begin(), corners.end());
    }
  }
  for (uint32_t v : coded) codes[v] = kUnknownCode;
  coded.clear();
}

// Self-shadowing (§7.2): the product's own triangles, when its vertices have S. Each vertex's
// clusters with a non-zero S as a bit set; a triangle carries cluster k when one of its corners
// does (the union of its corners' sets). Those unions are stored transposed, one bitmap of
// triangles per cluster, so that each pass, on the pool, visits only its own triangles in
// increasing order (the lowest set bit first), as many as a popcount says: the lists come out
// as the scan of every triangle made them, without testing all triangles in every pass.
// Reading the corners' S for every triangle and pass took 8 % of the demo session's profile;
// the per-pass scan of every triangle's set, 6.9 % under load; one serial sweep appending to
// every pass at once was slower still (pass list 2.2 ms against 1.3 ms).
void PassList::addProduct(const core::Mesh& product, const VertexS& s,
                          std::vector<raster::ShadowPass>& passes) {
  if (s.productS.empty()) {
    for (raster::ShadowPass& pass : passes) {
      pass.objectTriangles.clear();
      pass.objectS.clear();
    }
    return;
  }
  const size_t clusters = s.clusters, words = (clusters + 63) / 64;
  const size_t vertices = s.productS.size() / clusters, triangles = product.triangleCount();
  const size_t triangleWords = (triangles + 63) / 64;
  vertexClusters_.assign(vertices * words, 0);
  core::forEachChunk(pool_, vertices, 256, [&](size_t begin, size_t end, int) {
    for (size_t v = begin; v < end; ++v) {
      const core::Rgb16* row = &s.productS[v * clusters];
      uint64_t* bits = &vertexClusters_[v * words];
      for (size_t k = 0; k < clusters; ++k) {
        if (row[k].r != 0 || row[k].g != 0 || row[k].b != 0)
          bits[k / 64] |= uint64_t{1} << (k % 64);
      }
    }
  });
  // Chunks of whole 64-triangle words: each chunk writes only its own words of every bitmap.
  clusterTriangles_.assign(clusters * triangleWords, 0);
  core::forEachChunk(pool_, triangleWords, 4, [&](size_t begin, size_t end, int) {
    for (size_t t = begin * 64; t < std::min(end * 64, triangles); ++t) {
      const uint32_t* v = &product.indices[3 * t];
      const uint64_t bit = uint64_t{1} << (t % 64);
      for (size_t w = 0; w < words; ++w) {
        uint64_t set = vertexClusters_[v[0] * words + w] | vertexClusters_[v[1] * words + w] |
                       vertexClusters_[v[2] * words + w];
        for (; set != 0; set &= set - 1) {
          const size_t k = 64 * w + size_t(std::countr_zero(set));
          clusterTriangles_[k * triangleWords + t / 64] |= bit;
        }
      }
    }
  });
  core::forEachChunk(pool_, passes.size(), 1, [&](size_t i, size_t, int) {
    raster::ShadowPass& pass = passes[i];
    const size_t k = passCluster_[i];
    const uint64_t* row = &clusterTriangles_[k * triangleWords];
    size_t count = 0;
    for (size_t w = 0; w < triangleWords; ++w) count += size_t(std::popcount(row[w]));
    pass.objectTriangles.resize(count);
    pass.objectS.resize(3 * count);
    size_t n = 0;
    for (size_t w = 0; w < triangleWords; ++w) {
      for (uint64_t set = row[w]; set != 0; set &= set - 1, ++n) {
        const size_t t = 64 * w + size_t(std::countr_zero(set));
        const uint32_t* v = &product.indices[3 * t];
        pass.objectTriangles[n] = static_cast<uint32_t>(t);
        for (size_t c = 0; c < 3; ++c)
          pass.objectS[3 * n + c] = s.productS[size_t(v[c]) * clusters + k];
      }
    }
  });
}

}  // namespace penumbra::shadow
