#include "envmap/light_clustering.h"

#include <cmath>
#include <stdexcept>

#include "core/colour.h"
#include "scene/portable_trig.h"

namespace penumbra::envmap {

namespace {

// arcsin in degrees for s in [0, 1]: 64 halvings of [0°, 90°] (sine is increasing there;
// s = 1 exactly is 90°, which the halving would miss where the sine rounds to 1 early).
double arcsinDegrees(double s) {
  if (s >= 1.0) return 90.0;
  double lo = 0, hi = 90;
  for (int i = 0; i < 64; ++i) {
    const double mid = 0.5 * (lo + hi);
    double sine = 0, cosine = 0;
    scene::sinCosDegrees(mid, sine, cosine);
    (sine < s ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double clusterRadiusDegrees(uint32_t maxClusters, double correction) {
  if (maxClusters == 0) throw std::invalid_argument("light clustering: Q must be at least 1");
  if (!(correction > 0)) throw std::invalid_argument("light clustering: c_f must be positive");
  // Havran 2005 §4.3: 2π/Q = π sin² e, so e = arcsin √(2/Q), corrected by c_f.
  const double s = maxClusters <= 2 ? 1.0 : std::sqrt(2.0 / maxClusters);
  return correction * arcsinDegrees(s);
}

LightClusters clusterLights(const LightSet& lights, uint32_t maxClusters, double correction,
                            ClusterMemory* memory) {
  const double e = clusterRadiusDegrees(maxClusters, correction);
  double sine = 0, cosE = 0, cosWide = 0, cosNarrow = 0;
  scene::sinCosDegrees(std::min(180.0, e), sine, cosE);
  const double h = memory ? memory->hysteresis : 0.0;
  scene::sinCosDegrees(std::min(180.0, e * (1.0 + h)), sine, cosWide);
  scene::sinCosDegrees(std::min(180.0, e * (1.0 - h)), sine, cosNarrow);
  const auto lastSeed = [&](uint32_t id) {
    return memory && id < memory->seedOf.size() ? memory->seedOf[id] : 0u;
  };

  constexpr uint32_t kNone = UINT32_MAX;
  LightClusters out;
  out.clusterOf.assign(lights.size(), kNone);
  std::vector<size_t> seeds;
  for (size_t i = 0; i < lights.size(); ++i) {
    if (out.clusterOf[i] != kNone) continue;
    const uint32_t cluster = uint32_t(seeds.size());
    seeds.push_back(i);
    out.clusterOf[i] = cluster;
    const uint32_t seedId = lights[i].id;
    for (size_t j = i + 1; j < lights.size(); ++j) {
      if (out.clusterOf[j] != kNone) continue;
      // The paper's radius for a light the memory has not placed; wider for one that was
      // this seed's, narrower for one that was another's (or a seed itself).
      const uint32_t last = lastSeed(lights[j].id);
      const double threshold = last == 0 ? cosE : (last == seedId ? cosWide : cosNarrow);
      if (glm::dot(lights[i].direction, lights[j].direction) >= threshold)
        out.clusterOf[j] = cluster;
    }
  }
  // At most Q: a cluster beyond the Q-th goes to the nearest of the first Q seeds.
  std::vector<uint32_t> target(seeds.size());
  for (uint32_t c = 0; c < seeds.size(); ++c) {
    target[c] = c;
    if (c < maxClusters) continue;
    double best = -2;
    for (uint32_t q = 0; q < maxClusters; ++q) {
      const double d = glm::dot(lights[seeds[c]].direction, lights[seeds[q]].direction);
      if (d > best) best = d, target[c] = q;
    }
  }
  const size_t count = std::min<size_t>(seeds.size(), maxClusters);
  out.lights.resize(count);
  std::vector<glm::dvec3> weighted(count, glm::dvec3(0.0)), plain(count, glm::dvec3(0.0));
  for (size_t c = 0; c < count; ++c) out.lights[c].id = lights[seeds[c]].id;
  for (size_t i = 0; i < lights.size(); ++i) {
    const uint32_t c = target[out.clusterOf[i]];
    out.clusterOf[i] = c;
    out.lights[c].power += lights[i].power;
    weighted[c] += core::luminance(lights[i].power) * lights[i].direction;
    plain[c] += lights[i].direction;
  }
  for (size_t c = 0; c < count; ++c) {
    // The mean direction weighted by luminance power (the sampler gives the lights of a frame
    // equal luminance shares, so this is near the plain mean), renormalised; the plain mean
    // when the cluster has no power.
    glm::dvec3 d = glm::dot(weighted[c], weighted[c]) > 0 ? weighted[c] : plain[c];
    const double length = std::sqrt(glm::dot(d, d));
    out.lights[c].direction = length > 1e-12 ? d / length : lights[seeds[c]].direction;
  }
  if (memory) {
    for (const DirectionalLight& l : lights) {
      if (l.id >= memory->seedOf.size()) memory->seedOf.resize(size_t(l.id) + 1, 0);
    }
    for (size_t i = 0; i < lights.size(); ++i) {
      memory->seedOf[lights[i].id] = out.lights[out.clusterOf[i]].id;
    }
  }
  return out;
}

}  // namespace penumbra::envmap
