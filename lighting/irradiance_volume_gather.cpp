#include "lighting/irradiance_volume_gather.h"
#include "core/random.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/job_pool.h"
#include "scene/portable_trig.h"
#include "shadow/intensity_transfer.h"

namespace penumbra::lighting {
namespace {

// Adds radiance (*) weight (*) (A_l / pi) Y_k(dir) to the coefficients, in k order.
void accumulate(std::array<double, shadow::kShFloats>& c, const glm::dvec3& dir,
                const glm::dvec3& radiance, double weight) {
  double basis[shadow::kShCoefficients];
  shadow::shBasis9(dir.x, dir.y, dir.z, basis);
  for (int k = 0; k < shadow::kShCoefficients; ++k) {
    const double w = weight * shadow::kShIrradianceOverPi[size_t(k)] * basis[k];
    for (int ch = 0; ch < 3; ++ch) c[size_t(k) * 3 + size_t(ch)] += w * radiance[ch];
  }
}

}  // namespace

glm::dvec3 stratifiedSphereDirection(int n, uint64_t key, int sample) {
  const int a = sample / (2 * n), b = sample % (2 * n);
  // Row a: cos theta at the stratum's midpoint; its 2n azimuths equally spaced, the whole
  // row turned by a hashed offset (counter-based: key and row). Equal spacing integrates
  // the azimuthal factors of bands 0-2 exactly, the midpoints integrate z^2 to O(1/n^2),
  // and the per-row turn keeps rows from lining up with the room's edges.
  const double turn = core::unitInterval(core::splitmix64(key + core::kGolden * uint64_t(a)));
  const double z = 1.0 - 2.0 * (a + 0.5) / n;  // equal solid angle per row
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  double s, c;
  scene::sinCosDegrees(360.0 * (b + turn) / (2 * n), s, c);
  return {r * c, r * s, z};
}

std::array<double, shadow::kShFloats> projectIrradianceSh(
    const std::function<glm::dvec3(const glm::dvec3&)>& radiance, int n, uint64_t key) {
  if (n < 1) throw std::invalid_argument("projectIrradianceSh: directionsPerSide must be >= 1");
  std::array<double, shadow::kShFloats> c{};
  const int count = 2 * n * n;
  const double weight = 4.0 * std::numbers::pi / count;
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 d = stratifiedSphereDirection(n, key, i);
    accumulate(c, d, radiance(d), weight);
  }
  return c;
}

shadow::IrradianceVolume buildIrradianceVolume(const scene::PatchMesh& mesh,
                                               const EmbreeScene& rays,
                                               std::span<const glm::dvec3> patchRadiance,
                                               const IrradianceVolumeOptions& options) {
  if (patchRadiance.size() != mesh.patches.size()) {
    throw std::invalid_argument("buildIrradianceVolume: one radiance per patch expected");
  }
  if (options.dims.x < 1 || options.dims.y < 1 || options.dims.z < 1) {
    throw std::invalid_argument("buildIrradianceVolume: dims must be at least 1");
  }
  if (options.directionsPerSide < 1) {
    throw std::invalid_argument("buildIrradianceVolume: directionsPerSide must be >= 1");
  }
  if (mesh.positions.empty() || mesh.patches.empty()) {
    throw std::invalid_argument("buildIrradianceVolume: empty patch mesh");
  }
  scene::Aabb box = scene::Aabb::emptyBox();
  for (const glm::dvec3& p : mesh.positions) box.extend(p);

  shadow::IrradianceVolume vol;
  vol.dims = options.dims;
  const glm::dvec3 spacing = box.size() / glm::dvec3(options.dims);
  for (int a = 0; a < 3; ++a) {
    // A flat box (a single quad) still gets a positive spacing.
    vol.spacing[a] = static_cast<float>(spacing[a] > 0 ? spacing[a] : 1.0);
    vol.origin[a] = static_cast<float>(box.min[a] + 0.5 * spacing[a]);
  }
  const size_t count = vol.vertexCount();
  vol.coefficients.assign(count * shadow::kShFloats, 0.0f);
  vol.valid.assign(count, 0);

  std::vector<uint32_t> emitters;
  for (uint32_t j = 0; j < mesh.patches.size(); ++j) {
    if (mesh.patches[j].emits()) emitters.push_back(j);
  }
  const int n = options.directionsPerSide;
  const int samples = 2 * n * n;
  const double weight = 4.0 * std::numbers::pi / samples;

  // One pool per call (core/job_pool.h): this stage runs far longer than starting threads.
  core::JobPool pool(static_cast<int>(options.threads));
  pool.parallelFor(count, [&](size_t v, int) {
    const size_t i = v % options.dims.x, j = (v / options.dims.x) % options.dims.y,
                 k = v / (size_t{options.dims.x} * options.dims.y);
    // The same float position the lookup will use for this vertex.
    const glm::dvec3 x(double(vol.origin.x + float(i) * vol.spacing.x),
                       double(vol.origin.y + float(j) * vol.spacing.y),
                       double(vol.origin.z + float(k) * vol.spacing.z));
    std::array<double, shadow::kShFloats> c{};
    int bad = 0;
    const uint64_t key = core::splitmix64(options.seed ^ (uint64_t(v) * core::kGolden));
    for (int s = 0; s < samples; ++s) {
      const glm::dvec3 d = stratifiedSphereDirection(n, key, s);
      const std::optional<Hit> hit = rays.intersect(x, d);
      if (!hit) {
        ++bad;  // escaped: outside the room
        continue;
      }
      const uint32_t p = mesh.trianglePatch[hit->triangle];
      const scene::Patch& patch = mesh.patches[p];
      if (glm::dot(d, patch.normal) > 0) {
        ++bad;  // the back of a face: inside a solid box or outside the shell
        continue;
      }
      // Emission is added once per emitter below; rays see only the reflected part.
      accumulate(c, d, patchRadiance[p] - patch.emission, weight);
    }
    if (bad > options.invalidShare * samples) return;  // stays invalid, zero
    for (uint32_t e : emitters) {
      const scene::Patch& patch = mesh.patches[e];
      const glm::dvec3 target = patch.centre + options.normalOffset * patch.normal;
      const glm::dvec3 toward = target - x;
      const double r2 = glm::dot(toward, toward);
      if (!(r2 > 0)) continue;
      const glm::dvec3 d = toward / std::sqrt(r2);
      const double cosJ = -glm::dot(d, patch.normal);
      if (!(cosJ > 0)) continue;
      if (rays.occluded(x, target)) continue;
      const double solidAngle = patch.area * cosJ / (r2 + patch.area / std::numbers::pi);
      accumulate(c, d, patch.emission, solidAngle);
    }
    for (size_t q = 0; q < c.size(); ++q) {
      vol.coefficients[v * shadow::kShFloats + q] = static_cast<float>(c[q]);
    }
    vol.valid[v] = 1;
  });

  // Fallback: mean of the valid vertices, summed in vertex order.
  std::array<double, shadow::kShFloats> sum{};
  size_t validCount = 0;
  for (size_t v = 0; v < count; ++v) {
    if (!vol.valid[v]) continue;
    ++validCount;
    for (size_t q = 0; q < sum.size(); ++q) sum[q] += vol.coefficients[v * shadow::kShFloats + q];
  }
  for (size_t q = 0; q < sum.size(); ++q) {
    vol.fallback[q] = validCount ? static_cast<float>(sum[q] / double(validCount)) : 0.0f;
  }
  return vol;
}

}  // namespace penumbra::lighting
