#include "shadow/environment_light_transfers.h"

#include <cmath>
#include <stdexcept>

#include "core/clock.h"
#include "shadow/intensity_transfer.h"
#include "shadow/light_frustum.h"

namespace penumbra::shadow {
namespace {

// A distant light's shadow of the product is inside its box swept away from the light.
// Tested on three axes, d towards the light and u, v across it, with extent_X(a) =
// |a.x| h.x + |a.y| h.y + |a.z| h.z the half-width of box X along axis a. Proof that nothing
// shadowed is culled: a point q of a receiver box R shadowed by a point p of the product's
// box P (q = p - t d, t >= 0) has
//   (q - c).d = (p - c).d - t <= extent_P(d)   and   (q - c).u = (p - c).u,
// so |(q - c).u| <= extent_P(u); and q in R puts (q - c).a within extent_R(a) of
// (centre_R - c).a. Both intervals meet only if the three inequalities of mayShadow hold
// (on u and v: |b.u| - extent_R(u) <= extent_P(u)). Not exact — the swept box is not the
// product, and the three axes do not separate every miss — but far tighter than the product's
// bounding sphere swept (a square of side 2R across the light): for the chair seen from
// above the cross-section shrinks from 1.18 m to 0.58 m a side (0.48 m, widened below).
// The shadow map is filtered, though (docs/pipeline-spec.md §7: a bilinear lookup reaches one
// texel beyond the silhouette), so across the light the prism is widened to what the map can
// darken: fitDirectionalFrustum's window is the box's projection plus 3% of its width a side
// plus 0.1 mm, half-width 1.06 e + 1e-4 for the box's half-width e, and one texel of a map of
// at least 16 texels (the least a trace allows) adds at most 2 (1.06 e + 1e-4) / 16
// < 0.1325 e + 2e-5: in all under 1.2 e + 1e-3. A patch culled here has no pixel the pass could
// have changed, so the frame's bytes are those of the sphere's test.
struct ShadowPrism {
  static constexpr double kAcross = 1.2;
  glm::dvec3 centre{0.0}, d{0.0}, u{0.0}, v{0.0};
  glm::dvec3 reach{0.0};  // the product box's half-widths along d, u, v

  ShadowPrism(const scene::Aabb& product, const glm::dvec3& towardsLight)
      : centre(product.centre()), d(towardsLight) {
    u = glm::normalize(glm::cross(d, leastAlignedAxis(d)));
    v = glm::cross(d, u);
    const glm::dvec3 h = 0.5 * product.size();
    reach = {extent(d, h), kAcross * extent(u, h) + 1e-3, kAcross * extent(v, h) + 1e-3};
  }

  static double extent(const glm::dvec3& axis, const glm::dvec3& h) {
    return std::abs(axis.x) * h.x + std::abs(axis.y) * h.y + std::abs(axis.z) * h.z;
  }

  bool mayShadow(const scene::Aabb& box) const {
    const glm::dvec3 b = box.centre() - centre, h = 0.5 * box.size();
    return glm::dot(b, d) - extent(d, h) <= reach.x &&
           std::abs(glm::dot(b, u)) - extent(u, h) <= reach.y &&
           std::abs(glm::dot(b, v)) - extent(v, h) <= reach.z;
  }
};

}  // namespace

EnvironmentLightTransfers::EnvironmentLightTransfers(const SceneBundle& bundle,
                                                     const scene::PatchMesh& mesh,
                                                     const ShaftHierarchy& hierarchy)
    : bundle_(bundle),
      mesh_(mesh),
      hierarchy_(hierarchy),
      slots_(bundle.transfers, mesh),
      visibility_(mesh, bundle.transfers.receiverVertices, nullptr),
      patchFrame_(mesh.patches.size(), kNoIndex) {
  patchBounds_.reserve(mesh.patches.size());
  for (const scene::Patch& patch : mesh.patches) {
    scene::Aabb box = scene::Aabb::emptyBox();
    for (uint32_t k = 3 * patch.firstTriangle; k < 3 * patch.firstTriangle + 6; ++k) {
      box.extend(mesh.positions[mesh.indices[k]]);
    }
    patchBounds_.push_back(box);
  }
}

void EnvironmentLightTransfers::setPool(core::JobPool* pool) {
  pool_ = pool;
  rows_.resize(pool ? size_t(pool->threads()) : 1);
}

void EnvironmentLightTransfers::findReceivers(const DistantLights& lights,
                                              const scene::Aabb& productBounds, uint32_t frame) {
  const auto nodes = hierarchy_.receiverNodes();
  const auto order = hierarchy_.receiverOrder();
  lightPatches_.clear();
  lightPatchStart_.assign(1, 0);
  distinct_.clear();
  for (const glm::dvec3& towards : lights.towardsLight) {
    if (!nodes.empty() && !productBounds.empty()) {
      const ShadowPrism prism(productBounds, towards);
      stack_.assign(1, 0);  // the root
      while (!stack_.empty()) {
        const ShaftHierarchy::ReceiverNode& node = nodes[stack_.back()];
        stack_.pop_back();
        if (!prism.mayShadow(node.bounds)) continue;
        if (!node.isLeaf()) {
          // Children pushed last to first: popped, and so listed, in octree order.
          for (uint32_t c = node.childCount; c-- > 0;) stack_.push_back(node.firstChild + c);
          continue;
        }
        for (uint32_t i = node.firstPatch; i < node.firstPatch + node.patchCount; ++i) {
          const uint32_t patch = order[i];
          if (!prism.mayShadow(patchBounds_[patch])) continue;
          lightPatches_.push_back(patch);
          if (patchFrame_[patch] != frame) {
            patchFrame_[patch] = frame;
            distinct_.push_back(patch);
          }
        }
      }
    }
    lightPatchStart_.push_back(static_cast<uint32_t>(lightPatches_.size()));
  }
}

void EnvironmentLightTransfers::compute(const DistantLights& lights,
                                        const scene::Aabb& productBounds, uint32_t frame,
                                        const ProductLight& product) {
  if (lights.power.size() != lights.towardsLight.size()) {
    throw std::invalid_argument(
        "EnvironmentLightTransfers: " + std::to_string(lights.power.size()) + " powers for " +
        std::to_string(lights.towardsLight.size()) + " lights");
  }
  core::Stopwatch watch;
  const size_t count = lights.towardsLight.size();
  lights_ = count;
  findReceivers(lights, productBounds, frame);
  slots_.gather(mesh_, distinct_, frame);
  const std::span<const uint32_t> vertices = slots_.frameVertices();
  receiverS_.resize(vertices.size() * count);
  lookups_.resize(count);
  for (size_t k = 0; k < count; ++k) {
    lookups_[k] = StaticRoomVisibility::lookup(lights.towardsLight[k]);
  }
  // Rows are independent (each writes its own slot's shares, summing its lights in light
  // order): chunks on the pool give the serial bytes.
  core::forEachChunk(pool_, vertices.size(), kVertexChunk, [&](size_t begin, size_t end, int w) {
    std::vector<glm::dvec3>& e = rows_[size_t(w)];
    e.resize(count);
    for (size_t slot = begin; slot < end; ++slot) {
      const uint32_t r = vertices[slot];
      const glm::dvec3& n = mesh_.normals[bundle_.transfers.receiverVertices[r]];
      const bool open = visibility_.seesEverything(r);
      glm::dvec3 total(0.0);
      for (size_t k = 0; k < count; ++k) {
        const double cosine = glm::dot(n, lights.towardsLight[k]);
        const double seen = cosine > 0 && !open ? visibility_.visibility(r, lookups_[k]) : 1;
        e[k] = cosine > 0 ? lights.power[k] * (cosine * seen) : glm::dvec3(0.0);
        total += e[k];
      }
      lightShares(total, e, std::span<core::Rgb16>(receiverS_.data() + slot * count, count));
    }
  });
  nsReceivers_ = watch.lapNs();

  // The product's own vertices: light k's share of each vertex's unshadowed radiance.
  const size_t productVertices = product.positions.size();
  productS_.resize(productVertices * count);
  core::forEachChunk(pool_, productVertices, kVertexChunk, [&](size_t begin, size_t end, int w) {
    std::vector<glm::dvec3>& e = rows_[size_t(w)];
    e.resize(count);
    for (size_t v = begin; v < end; ++v) {
      for (size_t k = 0; k < count; ++k) e[k] = product.sourceTransfers[k * productVertices + v];
      lightShares(product.radiance[v], e,
                  std::span<core::Rgb16>(productS_.data() + v * count, count));
    }
  });
  nsProduct_ = watch.lapNs();
}

}  // namespace penumbra::shadow
