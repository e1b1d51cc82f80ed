#include "lighting/patch_radiosity.h"

#include <stdexcept>

#include "core/job_pool.h"

namespace penumbra::lighting {

std::vector<glm::dvec3> gatherPatchIrradiance(const scene::PatchMesh& mesh, const EmbreeScene& rays,
                                              std::span<const glm::dvec3> radiance,
                                              const GatherOptions& options) {
  const size_t n = mesh.patches.size();
  if (radiance.size() != n) {
    throw std::invalid_argument("gatherPatchIrradiance: one radiance per patch expected");
  }
  // Only patches that send light are visited (in index order).
  std::vector<uint32_t> senders;
  for (uint32_t j = 0; j < n; ++j) {
    const glm::dvec3& l = radiance[j];
    if (l.x > 0 || l.y > 0 || l.z > 0) senders.push_back(j);
  }
  std::vector<glm::dvec3> out(n, glm::dvec3(0.0));
  // One pool per call (core/job_pool.h): this stage runs far longer than starting threads.
  core::JobPool pool(static_cast<int>(options.threads));
  pool.parallelFor(n, [&](size_t i, int) {
    const scene::Patch& pi = mesh.patches[i];
    const glm::dvec3 from = pi.centre + options.normalOffset * pi.normal;
    glm::dvec3 sum(0.0);
    for (uint32_t j : senders) {
      if (j == i) continue;
      const scene::Patch& pj = mesh.patches[j];
      const double f =
          scene::pointToPatchFormFactor(pi.centre, pi.normal, pj.centre, pj.normal, pj.area);
      if (!(f > 0)) continue;  // facing away (either cosine clamped to 0)
      if (rays.occluded(from, pj.centre + options.normalOffset * pj.normal)) continue;
      sum += radiance[j] * f;
    }
    out[i] = sum;
  });
  return out;
}

std::vector<glm::dvec3> solvePatchRadiance(const scene::PatchMesh& mesh, const EmbreeScene& rays,
                                           int bounces, const GatherOptions& options) {
  if (bounces < 0) throw std::invalid_argument("solvePatchRadiance: bounces must be >= 0");
  std::vector<glm::dvec3> l(mesh.patches.size());
  for (size_t i = 0; i < l.size(); ++i) l[i] = mesh.patches[i].emission;
  for (int b = 0; b < bounces; ++b) {
    const std::vector<glm::dvec3> g = gatherPatchIrradiance(mesh, rays, l, options);
    for (size_t i = 0; i < l.size(); ++i) {
      l[i] = mesh.patches[i].emission + mesh.patches[i].reflectance * g[i];
    }
  }
  return l;
}

}  // namespace penumbra::lighting
