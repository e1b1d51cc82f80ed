#include "lighting/radiance_transfer.h"
#include "core/colour.h"
#include "core/random.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/job_pool.h"
#include "lighting/form_factor.h"
#include "shadow/intensity_transfer.h"

namespace penumbra::lighting {
namespace {

// Per-vertex surface properties, averaged over the vertex's distinct patches. Vertices
// are shared within a quad only (patch_mesh.h), so these are averages of neighbouring
// cells of one surface — what Gouraud interpolation of the photograph would show.
struct VertexMaterial {
  std::vector<glm::dvec3> reflectance, emission;
};

VertexMaterial vertexMaterials(const scene::PatchMesh& mesh) {
  const size_t vertexCount = mesh.positions.size();
  // Each patch's two triangles share two vertices; collecting (vertex, patch) pairs and
  // sorting them de-duplicates and fixes the summation order at once.
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  pairs.reserve(mesh.indices.size());
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) pairs.emplace_back(mesh.indices[3 * t + k], mesh.trianglePatch[t]);
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  VertexMaterial out;
  out.reflectance.assign(vertexCount, glm::dvec3(0.0));
  out.emission.assign(vertexCount, glm::dvec3(0.0));
  std::vector<uint32_t> count(vertexCount, 0);
  for (const auto& [v, p] : pairs) {
    out.reflectance[v] += mesh.patches[p].reflectance;
    out.emission[v] += mesh.patches[p].emission;
    ++count[v];
  }
  for (size_t v = 0; v < vertexCount; ++v) {
    if (count[v] == 0) continue;
    out.reflectance[v] /= static_cast<double>(count[v]);
    out.emission[v] /= static_cast<double>(count[v]);
  }
  return out;
}

void validate(const scene::PatchMesh& mesh, const shadow::SourceReceiverSets& sets,
              const TransferOptions& options) {
  if (options.samplesPerSide < 1) {
    throw std::invalid_argument("computeRadianceTransfers: samplesPerSide must be >= 1");
  }
  if (!(options.relativeThreshold >= 0) || !std::isfinite(options.relativeThreshold)) {
    throw std::invalid_argument("computeRadianceTransfers: relativeThreshold must be finite, >= 0");
  }
  if (mesh.trianglePatch.size() != mesh.triangleCount() ||
      mesh.normals.size() != mesh.positions.size()) {
    throw std::invalid_argument("computeRadianceTransfers: inconsistent patch mesh");
  }
  for (uint32_t v : mesh.indices) {
    if (v >= mesh.positions.size()) {
      throw std::invalid_argument("computeRadianceTransfers: vertex index out of range");
    }
  }
  for (uint32_t p : mesh.trianglePatch) {
    if (p >= mesh.patches.size()) {
      throw std::invalid_argument("computeRadianceTransfers: triangle patch out of range");
    }
  }
  for (const auto* list : {&sets.sources, &sets.receivers}) {
    for (uint32_t p : *list) {
      if (p >= mesh.patches.size() ||
          size_t{mesh.patches[p].firstTriangle} + 2 > mesh.triangleCount()) {
        throw std::invalid_argument("computeRadianceTransfers: patch " + std::to_string(p) +
                                    " out of range");
      }
    }
  }
}

}  // namespace

std::array<glm::dvec3, 4> patchPolygon(const scene::PatchMesh& mesh, uint32_t patch) {
  if (patch >= mesh.patches.size()) {
    throw std::invalid_argument("patchPolygon: patch out of range");
  }
  const size_t t = mesh.patches[patch].firstTriangle;
  if (3 * t + 6 > mesh.indices.size()) {
    throw std::invalid_argument("patchPolygon: patch triangles out of range");
  }
  const uint32_t* i = &mesh.indices[3 * t];
  if (i[3] != i[0] || i[4] != i[2]) {
    throw std::invalid_argument("patchPolygon: patch triangles are not (a, b, c), (a, c, d)");
  }
  return {mesh.positions.at(i[0]), mesh.positions.at(i[1]), mesh.positions.at(i[2]),
          mesh.positions.at(i[5])};
}

uint64_t visibilitySampleKey(uint64_t seed, uint32_t vertex, uint32_t patch) {
  // Two chained SplitMix64 steps: a different (vertex, patch) pair lands on an unrelated
  // stream even when the ids differ in one bit.
  return core::splitmix64(core::splitmix64(seed ^ (uint64_t{vertex} * core::kGolden)) ^ patch);
}

double pointToPatchVisibility(const EmbreeScene& rays, const glm::dvec3& x, const glm::dvec3& n,
                              const std::array<glm::dvec3, 4>& polygon, int samplesPerSide,
                              uint64_t key, double normalOffset) {
  const glm::dvec3 origin = x + normalOffset * n;
  const glm::dvec3 u = polygon[1] - polygon[0], v = polygon[3] - polygon[0];
  const double k = samplesPerSide;
  int inFront = 0, visible = 0;
  uint64_t counter = 0;
  for (int b = 0; b < samplesPerSide; ++b) {
    for (int a = 0; a < samplesPerSide; ++a) {
      const double js = core::unitInterval(core::splitmix64(key + core::kGolden * counter++));
      const double jt = core::unitInterval(core::splitmix64(key + core::kGolden * counter++));
      const glm::dvec3 p = polygon[0] + ((a + js) / k) * u + ((b + jt) / k) * v;
      // Samples behind the tangent plane are outside the clipped polygon the form factor
      // integrated over; a ray to them would only test the receiver's own surface.
      if (!(glm::dot(n, p - x) > 0)) continue;
      ++inFront;
      if (!rays.occluded(origin, p)) ++visible;
    }
  }
  if (inFront > 0) return static_cast<double>(visible) / inFront;
  // A sliver of the patch above the horizon that no sample hit: its centroid decides.
  const std::vector<glm::dvec3> clipped = clipPolygonToHemisphere(x, n, polygon);
  if (clipped.size() < 3) return 0;
  glm::dvec3 centroid(0.0);
  for (const glm::dvec3& p : clipped) centroid += p;
  centroid /= static_cast<double>(clipped.size());
  return rays.occluded(origin, centroid) ? 0.0 : 1.0;
}

shadow::RadianceTransfers computeRadianceTransfers(const scene::PatchMesh& mesh,
                                                   const shadow::SourceReceiverSets& sets,
                                                   const EmbreeScene& rays,
                                                   const TransferOptions& options) {
  validate(mesh, sets, options);
  shadow::RadianceTransfers out;

  // Receiver vertices: the corners of the receivers' two triangles, sorted and unique.
  std::vector<uint32_t>& receivers = out.receiverVertices;
  for (uint32_t p : sets.receivers) {
    const size_t t = mesh.patches[p].firstTriangle;
    for (size_t k = 0; k < 6; ++k) receivers.push_back(mesh.indices[3 * t + k]);
  }
  std::sort(receivers.begin(), receivers.end());
  receivers.erase(std::unique(receivers.begin(), receivers.end()), receivers.end());
  const size_t receiverCount = receivers.size();

  const VertexMaterial material = vertexMaterials(mesh);

  // Every emitting patch contributes to L_i (§7.1: L_i is the photograph's radiance, lit
  // by all sources); the source rows are a subset of these.
  std::vector<uint32_t> emitters;
  std::vector<int64_t> emitterSlot(mesh.patches.size(), -1);
  for (uint32_t p = 0; p < mesh.patches.size(); ++p) {
    if (!mesh.patches[p].emits()) continue;
    emitterSlot[p] = static_cast<int64_t>(emitters.size());
    emitters.push_back(p);
  }

  // transfer[e * receiverCount + i] = L_ij for emitter e, receiver vertex i.
  std::vector<glm::dvec3> transfer(emitters.size() * receiverCount, glm::dvec3(0.0));
  // One pool per call (core/job_pool.h): this stage runs far longer than starting threads.
  core::JobPool pool(static_cast<int>(options.threads));
  pool.parallelFor(emitters.size(), [&](size_t e, int) {
    const uint32_t j = emitters[e];
    const scene::Patch& patch = mesh.patches[j];
    const std::array<glm::dvec3, 4> polygon = patchPolygon(mesh, j);
    glm::dvec3* row = &transfer[e * receiverCount];
    for (size_t i = 0; i < receiverCount; ++i) {
      const uint32_t vertex = receivers[i];
      const glm::dvec3 rho = material.reflectance[vertex];
      if (!(core::luminance(rho) > 0)) continue;  // a pure emitter reflects nothing
      const glm::dvec3& x = mesh.positions[vertex];
      const glm::dvec3& n = mesh.normals[vertex];
      // Patches emit from their front side only (the facing convention of patch_mesh.h);
      // this also zeroes vertices in the emitter's own plane (its neighbours on a ceiling).
      if (!(glm::dot(patch.normal, x - patch.centre) > 0)) continue;
      const double f = pointToPolygonFormFactor(x, n, polygon);
      if (!(f > 0)) continue;
      const double visibility = pointToPatchVisibility(rays, x, n, polygon, options.samplesPerSide,
                                                       visibilitySampleKey(options.seed, vertex, j),
                                                       options.normalOffset);
      if (!(visibility > 0)) continue;
      row[i] = rho * patch.emission * (f * visibility);
    }
  });

  // L_i in a fixed order: own emission, then emitters by increasing patch index.
  std::vector<glm::dvec3> total(receiverCount);
  double maxLuminance = 0;
  for (size_t i = 0; i < receiverCount; ++i) {
    glm::dvec3 sum = material.emission[receivers[i]];
    for (size_t e = 0; e < emitters.size(); ++e) sum += transfer[e * receiverCount + i];
    total[i] = sum;
    maxLuminance = std::max(maxLuminance, core::luminance(sum));
  }
  out.vertexRadiance.reserve(receiverCount);
  for (const glm::dvec3& l : total) out.vertexRadiance.emplace_back(l);

  const double threshold = options.relativeThreshold * maxLuminance;
  out.sourceStart.reserve(sets.sources.size() + 1);
  out.sourceStart.push_back(0);
  out.sourceAverage.reserve(sets.sources.size());
  for (uint32_t j : sets.sources) {
    const int64_t e = emitterSlot[j];
    double luminanceSum = 0;
    if (e >= 0) {
      const glm::dvec3* row = &transfer[static_cast<size_t>(e) * receiverCount];
      for (size_t i = 0; i < receiverCount; ++i) {
        const double l = core::luminance(row[i]);
        luminanceSum += l;
        if (l > threshold) {
          out.entryVertex.push_back(static_cast<uint32_t>(i));
          out.entryTransfer.emplace_back(row[i]);
        }
      }
    }
    // The mean includes the dropped entries: it ranks sources (§7.1.1), and a source's
    // rank should not depend on the storage threshold.
    out.sourceAverage.push_back(
        receiverCount == 0 ? 0.0f
                           : static_cast<float>(luminanceSum / static_cast<double>(receiverCount)));
    out.sourceStart.push_back(static_cast<uint32_t>(out.entryVertex.size()));
  }
  return out;
}

std::vector<uint8_t> patchesVisibleFromCamera(const scene::PatchMesh& mesh, const EmbreeScene& rays,
                                              const glm::dmat4& viewProj, uint32_t width,
                                              uint32_t height) {
  if (width == 0 || height == 0) {
    throw std::invalid_argument("patchesVisibleFromCamera: image size must be non-zero");
  }
  if (mesh.trianglePatch.size() != mesh.triangleCount()) {
    throw std::invalid_argument("patchesVisibleFromCamera: inconsistent patch mesh");
  }
  const double det = glm::determinant(viewProj);
  if (!(std::abs(det) > 0) || !std::isfinite(det)) {
    throw std::invalid_argument("patchesVisibleFromCamera: viewProj is singular");
  }
  const glm::dmat4 inverse = glm::inverse(viewProj);
  auto unproject = [&](double x, double y, double z) {
    const glm::dvec4 p = inverse * glm::dvec4(x, y, z, 1.0);
    return glm::dvec3(p) / p.w;
  };
  std::vector<uint8_t> visible(mesh.patches.size(), 0);
  const double halfW = 0.5 * width, halfH = 0.5 * height;
  for (uint32_t py = 0; py < height; ++py) {
    const double ndcY = 1.0 - (py + 0.5) / halfH;
    for (uint32_t px = 0; px < width; ++px) {
      const double ndcX = (px + 0.5) / halfW - 1.0;
      const glm::dvec3 nearPoint = unproject(ndcX, ndcY, -1.0);
      const glm::dvec3 farPoint = unproject(ndcX, ndcY, 1.0);
      // t in [0, 1] spans near to far plane: the rasterizer's depth clip.
      const auto hit = rays.intersect(nearPoint, farPoint - nearPoint, 0.0, 1.0);
      if (hit && hit->triangle < mesh.trianglePatch.size()) {
        visible[mesh.trianglePatch[hit->triangle]] = 1;
      }
    }
  }
  return visible;
}

std::vector<uint8_t> patchesVisibleFromCamera(const scene::PatchMesh& mesh,
                                              const glm::dmat4& viewProj, uint32_t width,
                                              uint32_t height) {
  const EmbreeScene rays(mesh);
  return patchesVisibleFromCamera(mesh, rays, viewProj, width, height);
}

}  // namespace penumbra::lighting
