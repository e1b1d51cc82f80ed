#include "shadow/environment_light_transfers.h"

#include <cmath>
#include <stdexcept>

#include "core/clock.h"
#include "shadow/intensity_transfer.h"
#include "shadow/light_frustum.h"

namespace penumbra::shadow {
namespace {

// A distant light's shadow of a sphere is the half-infinite cylinder of the sphere's radius
// behind it. A box can hold a shadowed point only if some point of it lies no farther than R
// towards the light from the centre and its projection across the light overlaps the disc:
// tested on the box's extents along d and along two axes u, v across it (the square around
// the disc: conservative, never exact).
struct ShadowCylinder {
  glm::dvec3 centre{0.0}, d{0.0}, u{0.0}, v{0.0};
  double radius = 0;

  ShadowCylinder(const glm::dvec3& c, double r, const glm::dvec3& towardsLight)
      : centre(c), d(towardsLight), radius(r) {
    u = glm::normalize(glm::cross(d, leastAlignedAxis(d)));
    v = glm::cross(d, u);
  }

  bool mayShadow(const scene::Aabb& box) const {
    const glm::dvec3 b = box.centre() - centre, h = 0.5 * box.size();
    const auto extent = [&](const glm::dvec3& axis) {
      return std::abs(axis.x) * h.x + std::abs(axis.y) * h.y + std::abs(axis.z) * h.z;
    };
    return glm::dot(b, d) - extent(d) <= radius && std::abs(glm::dot(b, u)) - extent(u) <= radius &&
           std::abs(glm::dot(b, v)) - extent(v) <= radius;
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
      patchFrame_(mesh.patches.size(), kNoIndex) {}

void EnvironmentLightTransfers::setPool(core::JobPool* pool) {
  pool_ = pool;
  rows_.resize(pool ? size_t(pool->threads()) : 1);
}

void EnvironmentLightTransfers::findReceivers(const DistantLights& lights,
                                              const scene::Aabb& productBounds, uint32_t frame) {
  const auto nodes = hierarchy_.receiverNodes();
  const auto order = hierarchy_.receiverOrder();
  const glm::dvec3 centre = productBounds.centre();
  const double radius = 0.5 * glm::length(productBounds.size());
  lightPatches_.clear();
  lightPatchStart_.assign(1, 0);
  distinct_.clear();
  for (const glm::dvec3& towards : lights.towardsLight) {
    if (!nodes.empty() && !productBounds.empty()) {
      const ShadowCylinder cylinder(centre, radius, towards);
      stack_.assign(1, 0);  // the root
      while (!stack_.empty()) {
        const ShaftHierarchy::ReceiverNode& node = nodes[stack_.back()];
        stack_.pop_back();
        if (!cylinder.mayShadow(node.bounds)) continue;
        if (!node.isLeaf()) {
          // Children pushed last to first: popped, and so listed, in octree order.
          for (uint32_t c = node.childCount; c-- > 0;) stack_.push_back(node.firstChild + c);
          continue;
        }
        for (uint32_t i = node.firstPatch; i < node.firstPatch + node.patchCount; ++i) {
          const uint32_t patch = order[i];
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
