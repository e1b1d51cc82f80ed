#include "shadow/product_shading.h"

#include <numbers>
#include <stdexcept>
#include <string>

#include "scene/camera.h"
#include "shadow/patch_transfer.h"
#include "shadow/shaft_hierarchy.h"

namespace penumbra::shadow {

ProductShading::ProductShading(const SceneBundle& bundle, const scene::PatchMesh& mesh,
                               const scene::Aabb& room, const ProductShadingOptions& options)
    : bundle_(bundle),
      mesh_(mesh),
      options_(options),
      toneInverse_(bundle.tone),
      environmentFar_(2.0f * static_cast<float>(glm::length(room.size())) + 1.0f) {
  for (uint32_t p = 0; p < mesh_.patches.size(); ++p) {
    if (mesh_.patches[p].emits()) emitters_.push_back(p);
  }
  sourceOfPatch_.assign(mesh_.patches.size(), kNoIndex);
  for (size_t j = 0; j < bundle.sets.sources.size(); ++j) {
    sourceOfPatch_[bundle.sets.sources[j]] = static_cast<uint32_t>(j);
  }
  for (const ProductModel& m : bundle.products) lobes_.emplace_back(m.specularExponent);
  if (!bundle.patchRadiance.empty()) {
    environmentRoom_ = roomForEnvironment(bundle.view.staticMesh, bundle.trianglePatch,
                                          bundle.patchRadiance, bundle.tone);
  }
  // The camera centre: the point the view-projection sends to clip (0, 0, *, 0), i.e. the
  // homogeneous point inverse(VP) (0, 0, 1, 0).
  const glm::dvec4 e =
      glm::inverse(scene::fromRasterMat4(bundle.view.cameraViewProj)) * glm::dvec4(0, 0, 1, 0);
  if (e.w != 0) eye_ = glm::vec3(glm::dvec3(e) / e.w);
}

void ProductShading::shade(const core::Mesh& placed, const scene::Aabb& bounds, uint32_t product) {
  const std::vector<glm::vec3> normals = vertexNormals(placed);
  shade(placed, normals, bounds, product);
}

std::span<const glm::vec3> ProductShading::reflectancesOf(const ProductModel& model,
                                                          size_t vertices, size_t normals) const {
  if (normals != vertices) {
    throw std::invalid_argument("ProductShading::shade: " + std::to_string(normals) +
                                " normals for " + std::to_string(vertices) + " vertices");
  }
  // Per-vertex reflectance (the model's colours), or the product's one reflectance.
  if (model.reflectances.empty()) return {&model.reflectance, 1};
  if (model.reflectances.size() != vertices) {
    throw std::invalid_argument("ProductShading::shade: the placed mesh is not product " +
                                model.name + "'s");
  }
  return model.reflectances;
}

void ProductShading::shade(const core::Mesh& placed, std::span<const glm::vec3> normals,
                           const scene::Aabb& bounds, uint32_t product) {
  ++generation_;
  const core::Mesh& m = placed;
  const size_t vertices = m.positions.size();
  const ProductModel& model = bundle_.products.at(product);
  const std::span<const glm::vec3> reflectances = reflectancesOf(model, vertices, normals.size());
  const auto reflectanceOf = [&](size_t v) {
    return glm::dvec3(reflectances[reflectances.size() == 1 ? 0 : v]);
  };
  colours_.resize(vertices);
  radiance_.resize(vertices);
  sourceTransfers_.assign(bundle_.sets.sources.size() * vertices, glm::dvec3(0.0));
  // Vertices are independent (each writes its own entries): chunks of them on the pool.
  core::forEachChunk(pool_, vertices, kVertexChunk, [&](size_t begin, size_t end, int) {
    for (size_t v = begin; v < end; ++v) {
      const glm::dvec3 normal(normals[v]);
      const double length = glm::length(normal);
      const glm::dvec3 n = length > 0 ? normal / length : glm::dvec3(0, 1, 0);
      const glm::dvec3 x(m.positions[v].x, m.positions[v].y, m.positions[v].z);
      const glm::dvec3 reflectance = reflectanceOf(v);
      // Each emitter's transfer once: it adds to the vertex's radiance, and a source's is
      // kept as that source's L_ij for self-shadowing.
      glm::dvec3 radiance(0.0);
      for (uint32_t p : emitters_) {
        const scene::Patch& patch = mesh_.patches[p];
        const glm::dvec3 transfer = unshadowedTransfer(x, n, reflectance, patch);
        radiance += transfer;
        if (sourceOfPatch_[p] != kNoIndex)
          sourceTransfers_[sourceOfPatch_[p] * vertices + v] = transfer;
      }
      radiance_[v] = radiance;
      colours_[v] = bundle_.tone.map(radiance);
    }
  });
  if (bundle_.irradiance.empty() || !options_.shadeFromVolume) return;
  volumeRadiance_.resize(vertices);
  shadeVerticesDiffuse(bundle_.irradiance, m.positions, normals, reflectances, bundle_.tone,
                       colours_, volumeRadiance_);
  for (size_t v = 0; v < vertices; ++v) radiance_[v] = glm::dvec3(volumeRadiance_[v]);

  // §5 specular: the room reflected in a Phong lobe, from a cube map rendered at the
  // product's centre (Fig. 9), added in radiance before T().
  if (!options_.specular || environmentRoom_.mesh.positions.empty() ||
      !(model.specular.x > 0 || model.specular.y > 0 || model.specular.z > 0)) {
    return;
  }
  renderEnvironmentMap(environmentRoom_, glm::vec3(bounds.centre()), options_.environmentMapSize,
                       environmentFar_, environment_);
  const PhongLobe& lobe = lobes_[product];
  core::forEachChunk(pool_, vertices, kVertexChunk, [&](size_t begin, size_t end, int) {
    for (size_t v = begin; v < end; ++v) {
      const glm::vec3 p(m.positions[v].x, m.positions[v].y, m.positions[v].z);
      const glm::vec3 s = specularRadiance(environment_, toneInverse_, lobe, p, normals[v], eye_);
      const glm::vec3 l(volumeRadiance_[v].x + model.specular.x * s.x,
                        volumeRadiance_[v].y + model.specular.y * s.y,
                        volumeRadiance_[v].z + model.specular.z * s.z);
      radiance_[v] = glm::dvec3(l);
      colours_[v] = bundle_.tone.map(l);
    }
  });
}

void ProductShading::shadeFromLights(const core::Mesh& placed, std::span<const glm::vec3> normals,
                                     uint32_t product, std::span<const glm::dvec3> towardsLight,
                                     std::span<const glm::dvec3> power,
                                     std::span<const glm::dvec3> fineTowardsLight,
                                     std::span<const glm::dvec3> finePower) {
  ++generation_;
  const size_t vertices = placed.positions.size(), lights = towardsLight.size();
  const ProductModel& model = bundle_.products.at(product);
  const std::span<const glm::vec3> reflectances = reflectancesOf(model, vertices, normals.size());
  if (power.size() != lights) {
    throw std::invalid_argument("ProductShading::shadeFromLights: " + std::to_string(power.size()) +
                                " powers for " + std::to_string(lights) + " lights");
  }
  if (finePower.size() != fineTowardsLight.size()) {
    throw std::invalid_argument(
        "ProductShading::shadeFromLights: " + std::to_string(finePower.size()) + " powers for " +
        std::to_string(fineTowardsLight.size()) + " fine lights");
  }
  const glm::dvec3 specular(model.specular);
  const bool glossy = options_.specular && (specular.x > 0 || specular.y > 0 || specular.z > 0);
  const uint32_t n = lobes_[product].roundedExponent;
  // The normalised Phong lobe's peak: (N + 1) / (2 pi) integrates cos^N over the hemisphere
  // to 1, so a light of power P in the mirror direction gives radiance P (N + 1)/(2 pi).
  const double lobeScale = (n + 1.0) / (2.0 * std::numbers::pi);
  const bool strata = glossy && !fineTowardsLight.empty();
  // Havran 2005 §4.2's cone C about the mirror direction: where the lobe holds 90% of its
  // energy, cos^(N+1) θ = 0.1 (1 − c^(N+1) is the energy beyond polar cosine c), by bisection.
  double coneCos = 0;
  if (strata) {
    double lo = 0, hi = 1;
    for (int it = 0; it < 50; ++it) {
      const double mid = 0.5 * (lo + hi);
      (powInt(mid, n + 1) < 0.1 ? lo : hi) = mid;
    }
    coneCos = 0.5 * (lo + hi);
  }
  const auto lobe = [&](const glm::dvec3& mirror, const glm::dvec3& l, const glm::dvec3& p) {
    const double rl = glm::dot(mirror, l);
    return rl > 0 ? p * (lobeScale * powInt(rl, n)) : glm::dvec3(0.0);
  };
  colours_.resize(vertices);
  radiance_.resize(vertices);
  sourceTransfers_.assign(lights * vertices, glm::dvec3(0.0));
  core::forEachChunk(pool_, vertices, kVertexChunk, [&](size_t begin, size_t end, int) {
    for (size_t v = begin; v < end; ++v) {
      const glm::dvec3 normal(normals[v]);
      const double length = glm::length(normal);
      const glm::dvec3 nrm = length > 0 ? normal / length : glm::dvec3(0, 1, 0);
      const glm::dvec3 diffuse =
          glm::dvec3(reflectances[reflectances.size() == 1 ? 0 : v]) * (1.0 / std::numbers::pi);
      // r = 2 (n.e) n - e, e the unit direction to the kiosk's camera.
      glm::dvec3 mirror(0.0);
      if (glossy) {
        const glm::dvec3 toEye =
            glm::dvec3(eye_) -
            glm::dvec3(placed.positions[v].x, placed.positions[v].y, placed.positions[v].z);
        const double el = glm::length(toEye);
        if (el > 0) {
          const glm::dvec3 e = toEye / el;
          mirror = 2.0 * glm::dot(nrm, e) * nrm - e;
        }
      }
      glm::dvec3 radiance(0.0), diffuseSum(0.0), coarseOutside(0.0);
      for (size_t k = 0; k < lights; ++k) {
        const double cosine = glm::dot(nrm, towardsLight[k]);
        if (!(cosine > 0)) continue;  // below the vertex's horizon
        const glm::dvec3 lit = diffuse * (power[k] * cosine);
        glm::dvec3 transfer = lit;
        if (glossy) {
          const glm::dvec3 reflected = lobe(mirror, towardsLight[k], power[k]);
          transfer += specular * reflected;
          if (strata && glm::dot(mirror, towardsLight[k]) < coneCos) coarseOutside += reflected;
        }
        diffuseSum += lit;
        sourceTransfers_[k * vertices + v] = transfer;
        radiance += transfer;
      }
      radiance_[v] = radiance;
      if (!strata) {
        colours_[v] = bundle_.tone.map(radiance);
        continue;
      }
      // §4.2's two strata for the colour: inside the cone C the many faint lights (the
      // lobe's peak sampled finely), outside it the frame's lights. The passes' shares keep
      // the frame's lights (radiance_), whose shadows they cast.
      glm::dvec3 fineInside(0.0);
      for (size_t f = 0; f < fineTowardsLight.size(); ++f) {
        if (glm::dot(nrm, fineTowardsLight[f]) > 0 &&
            glm::dot(mirror, fineTowardsLight[f]) >= coneCos) {
          fineInside += lobe(mirror, fineTowardsLight[f], finePower[f]);
        }
      }
      colours_[v] = bundle_.tone.map(diffuseSum + specular * (fineInside + coarseOutside));
    }
  });
}

}  // namespace penumbra::shadow
